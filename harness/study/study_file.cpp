#include "harness/study/study_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <set>

#include <yaml-cpp/yaml.h>

#include "harness/metrics/registry.h"
#include "harness/scenario/overrides.h"

namespace corridorsim {
namespace {

const std::vector<std::string> kPipelineStats = {"mean", "median", "p95",    "min",
                                                 "max",  "ci_low", "ci_high"};
const std::vector<std::string> kNeesStats = {"average", "in_band_fraction"};
const std::vector<std::string> kRunStats = {"finished", "diverged"};
const std::vector<std::string> kPairedStats = {"diff",   "diff_ci_low",  "diff_ci_high",
                                               "ratio",  "ratio_ci_low", "ratio_ci_high",
                                               "p_sign", "p_wilcoxon"};

std::string Join(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

bool Contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

std::string Trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return "";
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

// A strict decimal number (no hex, inf, nan, trailing characters).
std::optional<double> ParseNumber(const std::string& text) {
  if (text.empty() || text.size() > 64) return std::nullopt;
  for (char c : text) {
    if (!((c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E')) {
      return std::nullopt;
    }
  }
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string FlowYaml(const YAML::Node& node) {
  YAML::Emitter out;
  out << YAML::Flow << node;
  return out.c_str();
}

// The sweep's keys as a tree, turned into one YAML map of scenario keys per point.
struct KeyTree {
  std::map<std::string, KeyTree> children;
  std::optional<YAML::Node> leaf;
  YAML::Node ToNode() const {
    if (leaf) return YAML::Clone(*leaf);
    YAML::Node node(YAML::NodeType::Map);
    for (const auto& [name, child] : children) node[name] = child.ToNode();
    return node;
  }
};

std::vector<std::string> SplitKey(const std::string& key) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = key.find('.', start);
    parts.push_back(key.substr(start, dot == std::string::npos ? std::string::npos : dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

bool IsKeyPart(const std::string& part) {
  return !part.empty() && part.size() <= 64 && std::all_of(part.begin(), part.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

struct Sweep {
  std::string key;
  SourceLocation key_location;
  std::vector<YAML::Node> values;
  std::vector<SourceLocation> value_locations;
};

std::vector<Sweep> ReadSweeps(const YamlDocument& doc, const YAML::Node& vary) {
  std::vector<Sweep> sweeps;
  if (!vary || vary.IsNull()) return sweeps;
  if (!vary.IsMap()) {
    throw InputError(doc.LocationOf(vary), "study.vary",
                     "must be a map of scenario keys to lists of values, e.g. "
                     "`vary: {robot.odometry.random_k_m: [1e-5, 1e-4]}`");
  }
  long points = 1;
  for (const auto& kv : vary) {
    Sweep sweep;
    sweep.key_location = doc.LocationOf(kv.first);
    if (!kv.first.IsScalar()) {
      throw InputError(sweep.key_location, "study.vary", "a key must be a dotted scenario key");
    }
    sweep.key = kv.first.Scalar();
    const std::string where = "study.vary." + InputExcerpt(sweep.key);
    const std::vector<std::string> parts = SplitKey(sweep.key);
    if (!std::all_of(parts.begin(), parts.end(), IsKeyPart) || parts.size() > 16) {
      throw InputError(sweep.key_location, where,
                       "a sweep key is a dotted scenario key such as world.plates.count");
    }
    static const std::set<std::string> kNotSwept = {"seed",         "include", "study",
                                                    "expectations", "name",    "description"};
    if (kNotSwept.count(parts[0])) {
      throw InputError(sweep.key_location, where,
                       "'" + parts[0] +
                           "' cannot be swept (the seeds are the study's runs; include, study, "
                           "expectations, name and description are not run settings)");
    }
    for (const Sweep& other : sweeps) {
      const std::vector<std::string> o = SplitKey(other.key);
      const std::size_t n = std::min(o.size(), parts.size());
      if (std::equal(o.begin(), o.begin() + static_cast<long>(n), parts.begin())) {
        throw InputError(sweep.key_location, where,
                         "overlaps the sweep key '" + other.key + "' (one holds the other)");
      }
    }
    const YAML::Node& list = kv.second;
    if (!list.IsSequence() || list.size() == 0 ||
        list.size() > static_cast<std::size_t>(kMaxSweepValues)) {
      throw InputError(sweep.key_location, where,
                       "must be a list of 1 to " + std::to_string(kMaxSweepValues) + " values");
    }
    for (const YAML::Node& value : list) {
      sweep.values.push_back(value);
      sweep.value_locations.push_back(doc.LocationOf(value));
    }
    points *= static_cast<long>(sweep.values.size());
    if (points > kMaxSweepPoints) {
      throw InputError(sweep.key_location, where,
                       "the sweep has more than " + std::to_string(kMaxSweepPoints) +
                           " points (the product of the lists' lengths)");
    }
    sweeps.push_back(std::move(sweep));
  }
  return sweeps;
}

std::vector<std::string> EnabledPipelines(const Scenario& scenario) {
  std::vector<std::string> names;
  for (const Scenario::PipelineEntry& e : scenario.pipelines) {
    if (e.enabled) names.push_back(e.name);
  }
  return names;
}

// The enabled pipelines the scenario marks `baseline: true`.
std::vector<std::string> Baselines(const Scenario& scenario) {
  std::vector<std::string> names;
  for (const Scenario::PipelineEntry& e : scenario.pipelines) {
    if (e.enabled && e.baseline) names.push_back(e.name);
  }
  return names;
}

void CheckExpectation(const StudySpec& spec, const StudyExpectation& e) {
  const auto fail = [&](const std::string& message) {
    throw InputError(e.location, "study.expectations",
                     "'" + InputExcerpt(e.text) + "': " + message);
  };
  const auto require_pipeline = [&](const std::string& name) {
    if (!Contains(spec.pipelines, name)) {
      fail("the pipeline '" + InputExcerpt(name) +
           "' does not run in this study (running: " + Join(spec.pipelines) + ")");
    }
  };
  const auto require_stat = [&](const std::vector<std::string>& stats) {
    if (!Contains(stats, e.stat)) {
      fail("unknown statistic '" + InputExcerpt(e.stat) + "' (expected one of: " + Join(stats) +
           ")");
    }
  };
  const auto require_metric = [&] {
    if (!Contains(spec.metrics, e.metric)) {
      fail("the metric '" + InputExcerpt(e.metric) +
           "' is not summarised (summarised: " + Join(spec.metrics) + "; add it to study.metrics)");
    }
  };
  switch (e.kind) {
    case StudyExpectation::Kind::kPipelineStat:
      require_pipeline(e.pipeline);
      require_metric();
      require_stat(kPipelineStats);
      break;
    case StudyExpectation::Kind::kNees:
      require_pipeline(e.pipeline);
      require_stat(kNeesStats);
      break;
    case StudyExpectation::Kind::kRuns:
      require_pipeline(e.pipeline);
      require_stat(kRunStats);
      break;
    case StudyExpectation::Kind::kPaired:
      require_pipeline(e.pipeline);
      require_pipeline(e.other);
      if (e.pipeline == e.other) fail("a pipeline paired with itself");
      require_metric();
      require_stat(kPairedStats);
      break;
    case StudyExpectation::Kind::kFailedRuns:
      break;
  }
}

// What the `study:` sections read so far leave: the study file's, then each --set's.
struct StudySection {
  std::vector<std::string> expectation_texts;  // the last section that has them wins
  std::vector<SourceLocation> expectation_locations;
  std::vector<Sweep> sweeps;  // the last `vary:` wins
};

// Reads the `study:` section of `top` (the study file, or one --set) onto `spec` and `section`.
void ReadStudySection(const YamlDocument& top, StudySpec* spec, StudySection& section) {
  SourceMap sources;
  YamlMap root(top, top.root, "", &sources);
  if (root.Has("study")) {
    spec->has_section = true;
    YamlMap study = root.Map("study");
    if (study.Read("runs", spec->runs) && (spec->runs < 1 || spec->runs > kMaxStudyRuns)) {
      study.Fail("runs", "must lie in [1, " + std::to_string(kMaxStudyRuns) + "] (got " +
                             std::to_string(spec->runs) + ")");
    }
    study.Read("first_seed", spec->first_seed);
    const auto bounded = [&](const char* key, double* value, double low, double high) {
      if (study.Read(key, *value) && !(*value >= low && *value <= high)) {
        char text[160];
        std::snprintf(text, sizeof text, "must lie in [%g, %g] (got %g)", low, high, *value);
        study.Fail(key, text);
      }
    };
    bounded("run_timeout_s", &spec->run_timeout_s, 1.0, kMaxRunTimeoutSeconds);
    bounded("divergence_nees", &spec->divergence_nees, 1.0, 1e12);
    bounded("time_step_s", &spec->time_step_s, 0.01, 3600.0);
    std::vector<std::string> extra;
    std::vector<SourceLocation> extra_locations;
    if (study.Read("metrics", extra, &extra_locations)) {
      if (extra.size() > static_cast<std::size_t>(kMaxStudyMetrics)) {
        study.Fail("metrics", "at most " + std::to_string(kMaxStudyMetrics) + " metrics");
      }
      const std::vector<std::string> names = MetricNames();
      for (std::size_t i = 0; i < extra.size(); ++i) {
        if (!metrics::IsKnownMetric(names, extra[i])) {
          throw InputError(extra_locations[i], "study.metrics",
                           "unknown metric '" + InputExcerpt(extra[i]) +
                               "' (docs/metrics.md lists a pipeline's metrics)");
        }
        if (!Contains(spec->metrics, extra[i])) spec->metrics.push_back(extra[i]);
      }
    }
    std::vector<std::string> texts;
    std::vector<SourceLocation> locations;
    if (study.Read("expectations", texts, &locations)) {
      section.expectation_texts = std::move(texts);
      section.expectation_locations = std::move(locations);
    }
    std::vector<std::string> may_diverge;
    std::vector<SourceLocation> may_diverge_locations;
    if (study.Read("may_diverge", may_diverge, &may_diverge_locations)) {
      AddMayDiverge(spec, may_diverge, "study.may_diverge", may_diverge_locations);
    }
    const bool vary = study.Has("vary");
    study.Accept("vary");
    study.RejectUnknownKeys();
    if (vary) section.sweeps = ReadSweeps(top, top.root["study"]["vary"]);
  }
}

// A --set of a key that the sweep varies would be overwritten at every point: refused.
void RejectSettingsOfSweepKeys(const std::vector<Setting>& settings,
                               const std::vector<Sweep>& sweeps) {
  for (const Setting& setting : settings) {
    for (const Sweep& sweep : sweeps) {
      const std::vector<std::string> parts = SplitKey(sweep.key);
      const std::size_t n = std::min(parts.size(), setting.parts.size());
      if (std::equal(parts.begin(), parts.begin() + static_cast<long>(n), setting.parts.begin())) {
        throw InputError(SourceLocation{kSetLocation, 0, 0}, InputExcerpt(setting.key),
                         "the study varies '" + sweep.key +
                             "' (study.vary), which every point sets: change the sweep's "
                             "values instead (--set 'study.vary={...}')");
      }
    }
  }
}

}  // namespace

const std::vector<std::string>& DefaultStudyMetrics() {
  static const std::vector<std::string> kMetrics = {"ate_rmse_m",          "ate_max_m",
                                                    "ate_yaw_rmse_rad",    "rpe_1m_trans_rmse_m",
                                                    "rpe_1m_yaw_rmse_rad", "final_position_error_m",
                                                    "final_yaw_error_rad", "nees_mean"};
  return kMetrics;
}

std::optional<std::string> ParseStudyExpectation(const std::string& text, StudyExpectation* out) {
  if (text.size() > 300) return std::string("an expectation is at most 300 characters");
  StudyExpectation e;
  e.text = text;
  std::size_t op_at = std::string::npos, op_len = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '<' || text[i] == '>') {
      op_at = i;
      const bool equal = i + 1 < text.size() && text[i + 1] == '=';
      op_len = equal ? 2 : 1;
      e.op = text[i] == '<'
                 ? (equal ? StudyExpectation::Op::kLessEqual : StudyExpectation::Op::kLess)
                 : (equal ? StudyExpectation::Op::kGreaterEqual : StudyExpectation::Op::kGreater);
      break;
    }
  }
  const std::string form =
      "expected '<pipeline>.<metric>.<stat> <op> <number>', "
      "'paired(<a>, <b>).<metric>.<stat> <op> <number>', '<pipeline>.nees.<stat> ...', "
      "'<pipeline>.runs.<stat> ...' or 'runs.failed ...', op one of < <= > >=";
  if (op_at == std::string::npos) return form;
  const std::string lhs = Trim(text.substr(0, op_at));
  const std::optional<double> value = ParseNumber(Trim(text.substr(op_at + op_len)));
  if (!value) return "the value after the operator is not a number (" + form + ")";
  e.value = *value;
  std::string rest;
  if (lhs.rfind("paired(", 0) == 0) {
    const std::size_t close = lhs.find(')');
    const std::size_t comma = lhs.find(',');
    if (close == std::string::npos || comma == std::string::npos || comma > close ||
        close + 1 >= lhs.size() || lhs[close + 1] != '.') {
      return form;
    }
    e.kind = StudyExpectation::Kind::kPaired;
    e.pipeline = Trim(lhs.substr(7, comma - 7));
    e.other = Trim(lhs.substr(comma + 1, close - comma - 1));
    rest = lhs.substr(close + 2);
  } else if (lhs == "runs.failed") {
    e.kind = StudyExpectation::Kind::kFailedRuns;
    e.stat = "failed";
    *out = e;
    return std::nullopt;
  } else {
    const std::size_t dot = lhs.find('.');
    if (dot == std::string::npos || dot == 0) return form;
    e.pipeline = lhs.substr(0, dot);
    rest = lhs.substr(dot + 1);
  }
  const std::size_t last = rest.rfind('.');
  if (last == std::string::npos || last == 0 || last + 1 >= rest.size()) return form;
  e.metric = rest.substr(0, last);
  e.stat = rest.substr(last + 1);
  if (e.kind != StudyExpectation::Kind::kPaired) {
    if (e.metric == "nees") {
      e.kind = StudyExpectation::Kind::kNees;
      e.metric.clear();
    } else if (e.metric == "runs") {
      e.kind = StudyExpectation::Kind::kRuns;
      e.metric.clear();
    }
  }
  *out = e;
  return std::nullopt;
}

void AddMayDiverge(StudySpec* spec, const std::vector<std::string>& names,
                   const std::string& option, const std::vector<SourceLocation>& locations) {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (!Contains(spec->pipelines, names[i])) {
      throw InputError(
          i < locations.size() ? locations[i] : SourceLocation{"command line", 0, 0}, option,
          "'" + InputExcerpt(names[i]) + "' is not a pipeline of this study (it runs " +
              Join(spec->pipelines) + ")");
    }
  }
  std::vector<std::string> merged;
  for (const std::string& name : spec->pipelines) {
    if (Contains(spec->may_diverge, name) || Contains(names, name)) merged.push_back(name);
  }
  spec->may_diverge = std::move(merged);
}

std::vector<JobInput> StudyInputs(const StudySpec& spec) {
  std::vector<JobInput> out;
  for (const StudyPoint& point : spec.points) {
    for (JobInput& input : ScenarioInputs(point.scenario)) {
      const bool seen = std::any_of(out.begin(), out.end(),
                                    [&](const JobInput& i) { return i.path == input.path; });
      if (!seen) out.push_back(std::move(input));
    }
  }
  return out;
}

StudySpec LoadStudy(const std::string& path, std::optional<int> runs,
                    std::optional<std::uint64_t> first_seed,
                    const std::vector<std::string>& settings) {
  StudySpec spec;
  spec.file = path;
  spec.metrics = DefaultStudyMetrics();
  // The chain and the --set keys, strictly (`study:` is skipped there).
  const Scenario base = LoadScenario(path, settings);
  spec.first_seed = base.seed;
  spec.pipelines = EnabledPipelines(base);
  RequireScoredPipeline(base);
  AddMayDiverge(&spec, Baselines(base), "baseline");  // a scenario's baselines may diverge

  const std::vector<YamlDocument> chain = LoadWithIncludes(path);
  const YamlDocument& top = chain.back();
  const std::vector<Setting> parsed_settings = ParseSettings(settings);
  // The file's `study:` section, then each --set's `study.*` keys (a later one wins; `metrics`
  // add up).
  std::vector<YamlDocument> sections = {top};
  for (YamlDocument& doc : SettingDocuments(parsed_settings, chain)) sections.push_back(doc);
  StudySection section;
  for (const YamlDocument& doc : sections) ReadStudySection(doc, &spec, section);
  const std::vector<Sweep>& sweeps = section.sweeps;
  const std::vector<std::string>& expectation_texts = section.expectation_texts;
  const std::vector<SourceLocation>& expectation_locations = section.expectation_locations;
  RejectSettingsOfSweepKeys(parsed_settings, sweeps);
  if (runs) spec.runs = *runs;
  if (first_seed) spec.first_seed = *first_seed;
  if (spec.first_seed >
      std::numeric_limits<std::uint64_t>::max() - static_cast<std::uint64_t>(spec.runs - 1)) {
    throw InputError(SourceLocation{path, 0, 0}, "study.first_seed",
                     "the seeds first_seed .. first_seed + runs - 1 overflow 64 bits");
  }
  for (const Sweep& s : sweeps) spec.vary_keys.push_back(s.key);

  // The points: every combination of the sweep's values, the last key varying fastest.
  std::size_t count = 1;
  for (const Sweep& s : sweeps) count *= s.values.size();
  if (static_cast<long>(count) * spec.runs > kMaxStudyTotalRuns) {
    throw InputError(SourceLocation{path, 0, 0}, "study.runs",
                     std::to_string(count) + " points x " + std::to_string(spec.runs) +
                         " runs is more than " + std::to_string(kMaxStudyTotalRuns) + " runs");
  }
  for (std::size_t index = 0; index < count; ++index) {
    StudyPoint point;
    char id[32];
    std::snprintf(id, sizeof id, "p%03zu", index);
    point.id = id;
    if (sweeps.empty()) {
      point.scenario = base;
      spec.points.push_back(std::move(point));
      continue;
    }
    KeyTree tree;
    std::size_t rest = index;
    std::vector<std::size_t> choice(sweeps.size());
    for (std::size_t k = sweeps.size(); k-- > 0;) {
      choice[k] = rest % sweeps[k].values.size();
      rest /= sweeps[k].values.size();
    }
    for (std::size_t k = 0; k < sweeps.size(); ++k) {
      const YAML::Node& value = sweeps[k].values[choice[k]];
      point.values.emplace_back(sweeps[k].key, FlowYaml(value));
      KeyTree* node = &tree;
      for (const std::string& part : SplitKey(sweeps[k].key)) node = &node->children[part];
      node->leaf = value;
    }
    YamlDocument overrides{top.file, tree.ToNode()};
    try {
      point.scenario = LoadScenario(path, settings, {overrides});
    } catch (const InputError& e) {
      // Placed at the value that caused it: the first key whose value is in the message's key.
      std::size_t culprit = 0;
      for (std::size_t k = 0; k < sweeps.size(); ++k) {
        if (e.key().rfind(sweeps[k].key, 0) == 0 || sweeps[k].key.rfind(e.key(), 0) == 0) {
          culprit = k;
        }
      }
      throw InputError(sweeps[culprit].value_locations[choice[culprit]],
                       "study.vary." + sweeps[culprit].key,
                       "value " + InputExcerpt(point.values[culprit].second) + ": " +
                           (e.key().empty() ? "" : e.key() + ": ") + e.message());
    }
    if (EnabledPipelines(point.scenario) != spec.pipelines) {
      throw InputError(sweeps.front().key_location, "study.vary." + sweeps.front().key,
                       "every point of a sweep must run the same pipelines (point " + point.id +
                           " runs " + Join(EnabledPipelines(point.scenario)) + ")");
    }
    if (Baselines(point.scenario) != Baselines(base)) {
      throw InputError(sweeps.front().key_location, "study.vary." + sweeps.front().key,
                       "every point of a sweep must have the same baselines (point " + point.id +
                           " has " + Join(Baselines(point.scenario)) + ", the study " +
                           Join(Baselines(base)) + ")");
    }
    spec.points.push_back(std::move(point));
  }

  for (std::size_t i = 0; i < expectation_texts.size(); ++i) {
    StudyExpectation e;
    if (auto error = ParseStudyExpectation(expectation_texts[i], &e)) {
      throw InputError(expectation_locations[i], "study.expectations",
                       "'" + InputExcerpt(expectation_texts[i]) + "': " + *error);
    }
    e.location = expectation_locations[i];
    CheckExpectation(spec, e);
    spec.expectations.push_back(std::move(e));
  }
  return spec;
}

}  // namespace corridorsim
