// The study's plan (study.json: what the runs' bytes and the summary depend on), read back for a
// merge; and the preparation of a study: the study file loaded, its folder prepared, and the runs
// of this shard that are still to run.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/sha256.h"
#include "common/io/stable_json.h"
#include "harness/run/provenance.h"
#include "harness/run/run_folder.h"
#include "harness/scenario/plugins.h"
#include "harness/study/study_file.h"
#include "harness/study/study_internal.h"

namespace corridorsim::study_internal {

namespace {

// The plan: everything the runs' bytes and the summary depend on, and nothing else (not the
// study file's path, the workers or the shard), so that a resumed, sharded or merged study can
// check that it continues the same study.
json PlanJson(const StudySpec& spec, const std::vector<std::string>& point_yaml) {
  json plan;
  plan["schema_version"] = 1;
  plan["build"] = ProjectVersion();
  plan["runs_per_point"] = spec.runs;
  plan["first_seed"] = spec.first_seed;
  plan["run_timeout_s"] = spec.run_timeout_s;
  plan["divergence_nees"] = spec.divergence_nees;
  plan["may_diverge"] = spec.may_diverge;
  plan["time_step_s"] = spec.time_step_s;
  plan["pipelines"] = spec.pipelines;
  plan["metrics"] = spec.metrics;
  plan["vary"] = spec.vary_keys;
  json points = json::array();
  for (std::size_t i = 0; i < spec.points.size(); ++i) {
    json values = json::object();
    for (const auto& [key, value] : spec.points[i].values) values[key] = value;
    points.push_back({{"id", spec.points[i].id},
                      {"vary", values},
                      {"scenario", "points/" + spec.points[i].id + ".yaml"},
                      {"scenario_sha256", Sha256Hex(point_yaml[i])}});
  }
  plan["points"] = std::move(points);
  json expectations = json::array();
  for (const StudyExpectation& e : spec.expectations) expectations.push_back(e.text);
  plan["expectations"] = std::move(expectations);
  // The plugin libraries the points load, with the SHA-256 of each when the study was planned:
  // a resumed study, a shard or a merge with a rebuilt plugin is another study.
  json plugins = json::array();
  std::set<fs::path> seen;
  for (const StudyPoint& point : spec.points) {
    for (const fs::path& path : point.scenario.plugins) {
      if (!seen.insert(path).second) continue;
      const LoadedPlugin* plugin = FindLoadedPlugin(path);
      plugins.push_back({{"path", path.string()}, {"sha256", plugin ? plugin->sha256 : ""}});
    }
  }
  plan["plugins"] = std::move(plugins);
  // The programs of external pipelines with the SHA-256 of the files their commands name: a
  // resumed study, a shard or a merge with an edited script is another study. Only when there
  // are some (the plans of other studies keep their bytes).
  json programs = json::array();
  std::set<std::string> seen_programs;
  for (const StudyPoint& point : spec.points) {
    const json by_pipeline = ExternalProgramsJson(point.scenario);
    if (by_pipeline.is_null()) continue;
    for (const auto& [name, fingerprint] : by_pipeline.items()) {
      json entry = {{"pipeline", name}, {"program", fingerprint}};
      if (seen_programs.insert(JsonText(entry)).second) programs.push_back(std::move(entry));
    }
  }
  if (!programs.empty()) plan["external_programs"] = std::move(programs);
  return plan;
}

}  // namespace

// What differs between two plans' plugin libraries ("" when nothing): the merge names it.
std::string PluginDifference(const json& a, const json& b) {
  const json none = json::array();
  const json& pa = a.contains("plugins") ? a["plugins"] : none;
  const json& pb = b.contains("plugins") ? b["plugins"] : none;
  if (pa == pb) return "";
  for (const json& x : pa) {
    for (const json& y : pb) {
      if (x.value("path", "") == y.value("path", "") &&
          x.value("sha256", "") != y.value("sha256", "")) {
        return "the plugin library " + x.value("path", "") + " differs (SHA-256 " +
               x.value("sha256", "") + " against " + y.value("sha256", "") + ")";
      }
    }
  }
  return "their plugin libraries differ";
}

// The summary's view of a plan (for `merge`, which has the folders, not the study file).
StudySpec SpecFromPlan(const json& plan, const fs::path& file) {
  StudySpec spec;
  try {
    spec.runs = plan.at("runs_per_point").get<int>();
    spec.first_seed = plan.at("first_seed").get<std::uint64_t>();
    spec.run_timeout_s = plan.at("run_timeout_s").get<double>();
    spec.divergence_nees = plan.at("divergence_nees").get<double>();
    spec.may_diverge = plan.at("may_diverge").get<std::vector<std::string>>();
    spec.time_step_s = plan.at("time_step_s").get<double>();
    spec.pipelines = plan.at("pipelines").get<std::vector<std::string>>();
    spec.metrics = plan.at("metrics").get<std::vector<std::string>>();
    spec.vary_keys = plan.at("vary").get<std::vector<std::string>>();
    for (const json& p : plan.at("points")) {
      StudyPoint point;
      point.id = p.at("id").get<std::string>();
      for (const auto& [key, value] : p.at("vary").items()) {
        point.values.emplace_back(key, value.get<std::string>());
      }
      spec.points.push_back(std::move(point));
    }
    for (const json& text : plan.at("expectations")) {
      StudyExpectation e;
      if (auto error = ParseStudyExpectation(text.get<std::string>(), &e)) {
        throw std::runtime_error(*error);
      }
      spec.expectations.push_back(std::move(e));
    }
  } catch (const std::exception& e) {
    throw InputError(SourceLocation{file.string(), 0, 0}, "",
                     std::string("not a study plan of this build: ") + e.what());
  }
  if (spec.runs < 1 || spec.runs > kMaxStudyRuns || spec.points.empty() ||
      spec.points.size() > static_cast<std::size_t>(kMaxSweepPoints) || spec.pipelines.empty() ||
      spec.metrics.empty()) {
    throw InputError(SourceLocation{file.string(), 0, 0}, "", "a study plan out of bounds");
  }
  return spec;
}

json ReadPlan(const fs::path& file) {
  try {
    return json::parse(ReadRegularFile(file, kMaxPlanBytes));
  } catch (const json::exception& e) {
    throw InputError(SourceLocation{file.string(), 0, 0}, "", std::string("not JSON: ") + e.what());
  }
}

PreparedStudy PrepareStudy(const StudyRequest& request) {
  PreparedStudy p;
  p.spec = LoadStudy(request.scenario_file, request.runs, request.seed, request.settings);
  AddMayDiverge(&p.spec, request.may_diverge, "--may-diverge");
  const StudySpec& spec = p.spec;
  std::vector<std::string> point_yaml;
  for (const StudyPoint& point : spec.points) {
    point_yaml.push_back(ResolvedScenarioYaml(point.scenario, spec.first_seed));
  }
  const std::string plan_text = JsonFileText(PlanJson(spec, point_yaml));
  p.dir = request.out_dir;
  RefuseOutputOverInputs(p.dir, "--out", StudyInputs(spec));
  PrepareFolder(p.dir, plan_text, request.force, "--out");
  for (std::size_t i = 0; i < spec.points.size(); ++i) {
    const fs::path file = p.dir / "points" / (spec.points[i].id + ".yaml");
    std::error_code error;
    fs::create_directories(file.parent_path(), error);
    WriteFileAtomic(file, point_yaml[i]);
  }
  // Whether the runs can share their seed's stream: a local study only (--slurm measures one
  // run and writes scripts; its tasks decide for their shards).
  if (request.replay && !request.slurm && spec.points.size() > 1) {
    p.stream = DecideStreamSharing(spec, point_yaml);
  }
  if (request.shard_count > 1) {
    WriteFileAtomic(p.dir / "shard.json", JsonFileText(json{{"shard", request.shard_index + 1},
                                                            {"of", request.shard_count}}));
  }
  // The runs of this shard (run k of the plan belongs to shard k mod N) not finished yet.
  long index = 0;
  for (std::size_t point = 0; point < spec.points.size(); ++point) {
    for (int i = 0; i < spec.runs; ++i, ++index) {
      if (index % request.shard_count != request.shard_index) continue;
      ++p.planned_here;
      const std::uint64_t seed = spec.first_seed + static_cast<std::uint64_t>(i);
      std::error_code error;
      if (fs::is_regular_file(RunFolder(p.dir, spec.points[point].id, seed) / "metrics.json",
                              error)) {
        ++p.already;
        continue;
      }
      p.todo.push_back({point, seed});
    }
  }
  return p;
}

}  // namespace corridorsim::study_internal
