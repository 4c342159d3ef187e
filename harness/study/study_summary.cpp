#include "harness/study/study_summary.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "harness/metrics/stats.h"
#include "harness/study/study_stats.h"

namespace corridorsim {
namespace {

using json = nlohmann::ordered_json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::uint64_t kMaxMetricsBytes = std::uint64_t{64} << 20;
constexpr std::uint64_t kMaxErrorsBytes = std::uint64_t{512} << 20;
constexpr int kPoseDof = 3;              // NEES of the planar pose (x, y, yaw)
constexpr double kMaxStampS = 1e9;       // a run's stamps: no run is 30 years long
constexpr int kMaxSeriesPoints = 20000;  // the series' grid is coarsened beyond this

// Statistics are written with 9 significant digits: the same bytes from the same inputs, and no
// 17-digit tails.
json Num(double v) {
  if (!std::isfinite(v)) return nullptr;
  char text[40];
  std::snprintf(text, sizeof text, "%.9g", v);
  return std::strtod(text, nullptr);
}
std::string CsvNum(double v) {
  if (!std::isfinite(v)) return "";
  char text[40];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

double Mean(const std::vector<double>& v) {
  return v.empty() ? kNaN
                   : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

// The value at a dotted path of a JSON object, when it is a finite number.
std::optional<double> NumberAt(const json& root, const std::string& dotted) {
  const json* node = &root;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = dotted.find('.', start);
    const std::string part = dotted.substr(start, dot == std::string::npos ? dot : dot - start);
    if (!node->is_object()) return std::nullopt;
    const auto it = node->find(part);
    if (it == node->end()) return std::nullopt;
    node = &*it;
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  if (!node->is_number()) return std::nullopt;
  const double v = node->get<double>();
  return std::isfinite(v) ? std::optional(v) : std::nullopt;
}

struct ErrorSample {
  double t, ex, ey, eyaw, sx, sy, syaw, nees;  // nees NaN when absent
};

// <pipeline>_errors.csv (harness/metrics/consistency.h): t,ex_m,ey_m,eyaw_rad,sigma_x_m,
// sigma_y_m,sigma_yaw_rad,nees.
std::vector<ErrorSample> ReadErrors(const std::filesystem::path& file) {
  const std::string text = ReadRegularFile(file, kMaxErrorsBytes);
  std::vector<ErrorSample> samples;
  std::size_t pos = text.find('\n');
  if (pos == std::string::npos ||
      text.compare(0, pos, "t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees") != 0) {
    throw std::runtime_error(file.string() + ": not an errors CSV of this build");
  }
  ++pos;
  for (int line = 2; pos < text.size(); ++line) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    const char* p = text.c_str() + pos;
    double v[8];
    int fields = 0;
    for (; fields < 8; ++fields) {
      char* next = nullptr;
      v[fields] = std::strtod(p, &next);
      if (next == p) {
        v[fields] = kNaN;  // an empty field (the NEES before the covariance is regular)
      }
      p = next;
      if (fields < 7) {
        if (*p != ',') break;
        ++p;
      }
    }
    if (fields < 7) {
      throw InputError({file.string(), line, 1}, "", "a malformed line (8 comma-separated fields)");
    }
    // The series' grid is laid over the stamps: one that is no time (inf, nan, negative, beyond
    // the longest run) would make it endless.
    if (!(v[0] >= 0) || !(v[0] < kMaxStampS)) {
      char value[32];
      std::snprintf(value, sizeof value, "%g", v[0]);
      throw InputError({file.string(), line, 1}, "t",
                       std::string("the stamp ") + value + " is not a time in [0, 1e9) s");
    }
    samples.push_back({v[0], v[1], v[2], v[3], v[4], v[5], v[6], fields == 8 ? v[7] : kNaN});
    pos = end + 1;
  }
  return samples;
}

// NIS of one landmark type pooled in bins of the study's time step: per bin, the accepted
// innovations of every run (count, sum of NIS, sum of degrees of freedom).
struct NisBin {
  double count = 0, nis_sum = 0, dof_sum = 0;
};
using NisBins = std::map<std::string, std::map<long, NisBin>>;  // type -> bin -> pooled

// <pipeline>_nis.csv (harness/metrics/consistency.h): t,type,dof,nis,accepted. A run without
// landmark updates has none.
void ReadNis(const std::filesystem::path& file, double step_s, NisBins* bins) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(file, error)) return;
  const std::string text = ReadRegularFile(file, kMaxErrorsBytes);
  std::size_t pos = text.find('\n');
  if (pos == std::string::npos || text.compare(0, pos, "t,type,dof,nis,accepted") != 0) {
    throw std::runtime_error(file.string() + ": not a NIS CSV of this build");
  }
  ++pos;
  while (pos < text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    // Fields by their commas, within this line (no copy of the line).
    std::size_t comma[4];
    std::size_t from = pos;
    for (std::size_t& c : comma) {
      c = text.find(',', from);
      if (c >= end) throw std::runtime_error(file.string() + ": a malformed line");
      from = c + 1;
    }
    const char* p = text.c_str();
    const double t = std::strtod(p + pos, nullptr);
    const double dof = std::strtod(p + comma[1] + 1, nullptr);
    const double nis = std::strtod(p + comma[2] + 1, nullptr);
    if (!(t >= 0) || !(t < kMaxStampS) || !(dof >= 1) || !(nis >= 0) || !std::isfinite(nis)) {
      throw std::runtime_error(file.string() + ": a line out of range");
    }
    const bool applied = end - comma[3] == 2 && text[comma[3] + 1] == '1';
    if (applied) {
      NisBin& bin = (*bins)[text.substr(comma[0] + 1, comma[1] - comma[0] - 1)]
                           [static_cast<long>(t / step_s)];
      bin.count += 1;
      bin.nis_sum += nis;
      bin.dof_sum += dof;
    }
    pos = end + 1;
  }
}

// The NIS of each type over time: bins of step_s merged k at a time so that at most
// kMaxSeriesPoints remain; per bin the mean NIS of the pooled innovations against the 95 % band
// of the mean of K chi-square values, [chi2(sum d, 0.025) / K, chi2(sum d, 0.975) / K].
void AddNisSeries(const NisBins& bins, double step_s, json* nis_json) {
  for (const auto& [type, by_bin] : bins) {  // a type is there with at least one bin
    const long last = by_bin.rbegin()->first;
    const long k = std::max<long>(1, (last + kMaxSeriesPoints) / kMaxSeriesPoints);
    std::map<long, NisBin> merged;
    for (const auto& [index, bin] : by_bin) {
      NisBin& m = merged[index / k];
      m.count += bin.count;
      m.nis_sum += bin.nis_sum;
      m.dof_sum += bin.dof_sum;
    }
    json t = json::array(), count = json::array(), anis = json::array(), low = json::array(),
         high = json::array();
    double sum = 0;
    int inside = 0;
    for (const auto& [index, bin] : merged) {
      const double a = bin.nis_sum / bin.count;
      const double lo =
          metrics::ChiSquareQuantile(bin.dof_sum, metrics::kBandLowerTail) / bin.count;
      const double hi =
          metrics::ChiSquareQuantile(bin.dof_sum, metrics::kBandUpperTail) / bin.count;
      t.push_back(Num(static_cast<double>(index * k) * step_s));
      count.push_back(bin.count);
      anis.push_back(Num(a));
      low.push_back(Num(lo));
      high.push_back(Num(hi));
      sum += a;
      inside += a >= lo && a <= hi;
    }
    json& out = (*nis_json)[type];
    out["time_average"] = Num(sum / static_cast<double>(merged.size()));
    out["time_in_band_fraction"] =
        Num(static_cast<double>(inside) / static_cast<double>(merged.size()));
    out["series"] = {{"step_s", Num(static_cast<double>(k) * step_s)},
                     {"t", std::move(t)},
                     {"count", std::move(count)},
                     {"anis", std::move(anis)},
                     {"band_low", std::move(low)},
                     {"band_high", std::move(high)}};
  }
}

json Describe(const std::vector<double>& values, const std::string& stream) {
  json out;
  out["n"] = values.size();
  if (values.empty()) {
    for (const char* k : {"mean", "std", "median", "p95", "min", "max", "ci_low", "ci_high"}) {
      out[k] = nullptr;
    }
    return out;
  }
  const double mean = Mean(values);
  double ss = 0.0;
  for (double v : values) ss += (v - mean) * (v - mean);
  const study::Interval ci = study::BootstrapMeanInterval(values, stream);
  out["mean"] = Num(mean);
  out["std"] = values.size() > 1 ? Num(std::sqrt(ss / static_cast<double>(values.size() - 1)))
                                 : json(nullptr);
  out["median"] = Num(study::Quantile(values, 0.5));
  out["p95"] = Num(study::Quantile(values, 0.95));
  out["min"] = Num(*std::min_element(values.begin(), values.end()));
  out["max"] = Num(*std::max_element(values.begin(), values.end()));
  out["ci_low"] = Num(ci.low);
  out["ci_high"] = Num(ci.high);
  return out;
}

// Why a pipeline's run counts as diverged (docs/studies.md, "Failures"), or nothing.
std::optional<std::string> DivergedWhy(const json& m, double divergence_nees) {
  const auto count = [&](const char* key) {
    return NumberAt(m, std::string("health.") + key).value_or(0.0);
  };
  char text[160];
  if (count("failed") > 0) return std::string("failed (a call into it threw; events.json)");
  if (const double n = count("non_finite_estimates"); n > 0) {
    std::snprintf(text, sizeof text, "non-finite estimates (%.0f)", n);
    return std::string(text);
  }
  if (const double n = count("non_positive_covariance"); n > 0) {
    std::snprintf(text, sizeof text, "non-positive covariance (%.0f)", n);
    return std::string(text);
  }
  const auto nees = NumberAt(m, "nees_mean");
  if (!nees) return "no average NEES";
  if (!NumberAt(m, "ate_rmse_m")) return "no ATE";
  if (*nees > divergence_nees) {
    std::snprintf(text, sizeof text, "average NEES %.4g > divergence_nees %g", *nees,
                  divergence_nees);
    return std::string(text);
  }
  return std::nullopt;
}

// One pipeline at one point: its per-run values and series.
struct PipelineRuns {
  std::vector<std::uint64_t> seeds;                               // finished runs, in seed order
  std::map<std::string, std::map<std::uint64_t, double>> values;  // metric -> seed -> value
  std::vector<std::uint64_t> diverged;
  std::vector<std::string> diverged_why;  // parallel to `diverged`
  std::vector<std::vector<ErrorSample>> series;
  struct Nis {
    double count = 0, weighted_sum = 0;
    int runs = 0, runs_in_band = 0;
    double in_band_fraction_sum = 0;
  };
  std::map<std::string, Nis> nis;  // landmark type -> pooled
  NisBins nis_bins;                // landmark type -> time bin -> pooled
};

json SeriesJson(const std::vector<std::vector<ErrorSample>>& runs, double step_s, double* average,
                double* in_band_fraction) {
  double t_end = 0.0;
  for (const auto& r : runs) {
    if (!r.empty()) t_end = std::max(t_end, r.back().t);
  }
  const double step = std::max(step_s, t_end / kMaxSeriesPoints);
  const auto points = static_cast<std::size_t>(std::floor(t_end / step)) + 1;
  json t = json::array(), n = json::array(), anees = json::array(), low = json::array(),
       high = json::array(), err = json::array(), sigma = json::array(), ex = json::array(),
       ey = json::array(), err_n_series = json::array();
  // Per axis (P3 Fig. 18's rows): the RMS error over runs and the RMS of the filters' sigma.
  const char* kAxes[3] = {"x_m", "y_m", "yaw_rad"};
  json axis_err[3] = {json::array(), json::array(), json::array()};
  json axis_sigma[3] = {json::array(), json::array(), json::array()};
  std::vector<std::size_t> cursor(runs.size(), 0);
  double anees_sum = 0.0;
  int anees_points = 0, inside = 0;
  for (std::size_t i = 0; i < points; ++i) {
    const double grid = static_cast<double>(i) * step;
    double nees_sum = 0.0, e2 = 0.0, s2 = 0.0, sx = 0.0, sy = 0.0;
    double axis_e2[3] = {0, 0, 0}, axis_s2[3] = {0, 0, 0};
    int nees_n = 0, err_n = 0;
    for (std::size_t r = 0; r < runs.size(); ++r) {
      // Each run's first sample at or after the grid time, within the step.
      std::size_t& c = cursor[r];
      while (c < runs[r].size() && runs[r][c].t < grid) ++c;
      if (c >= runs[r].size() || runs[r][c].t >= grid + step) continue;
      const ErrorSample& s = runs[r][c];
      if (std::isfinite(s.ex) && std::isfinite(s.ey)) {
        e2 += s.ex * s.ex + s.ey * s.ey;
        s2 += s.sx * s.sx + s.sy * s.sy;
        sx += s.ex;
        sy += s.ey;
        const double e[3] = {s.ex, s.ey, s.eyaw}, sd[3] = {s.sx, s.sy, s.syaw};
        for (int k = 0; k < 3; ++k) {
          axis_e2[k] += std::isfinite(e[k]) ? e[k] * e[k] : 0.0;
          axis_s2[k] += std::isfinite(sd[k]) ? sd[k] * sd[k] : 0.0;
        }
        ++err_n;
      }
      if (std::isfinite(s.nees)) {
        nees_sum += s.nees;
        ++nees_n;
      }
    }
    if (err_n == 0 && nees_n == 0) continue;
    t.push_back(Num(grid));
    n.push_back(nees_n);
    err_n_series.push_back(err_n);
    for (int k = 0; k < 3; ++k) {
      axis_err[k].push_back(err_n ? Num(std::sqrt(axis_e2[k] / err_n)) : json(nullptr));
      axis_sigma[k].push_back(err_n ? Num(std::sqrt(axis_s2[k] / err_n)) : json(nullptr));
    }
    err.push_back(err_n ? Num(std::sqrt(e2 / err_n)) : json(nullptr));
    sigma.push_back(err_n ? Num(std::sqrt(s2 / err_n)) : json(nullptr));
    ex.push_back(err_n ? Num(sx / err_n) : json(nullptr));
    ey.push_back(err_n ? Num(sy / err_n) : json(nullptr));
    if (nees_n == 0) {
      anees.push_back(nullptr);
      low.push_back(nullptr);
      high.push_back(nullptr);
      continue;
    }
    // The mean of N chi-square(3) values lies in [chi2(3N, 0.025) / N, chi2(3N, 0.975) / N]
    // (Bar-Shalom, Li and Kirubarajan 2001, section 5.4.2).
    const double a = nees_sum / nees_n;
    const double lo =
        metrics::ChiSquareQuantile(kPoseDof * nees_n, metrics::kBandLowerTail) / nees_n;
    const double hi =
        metrics::ChiSquareQuantile(kPoseDof * nees_n, metrics::kBandUpperTail) / nees_n;
    anees.push_back(Num(a));
    low.push_back(Num(lo));
    high.push_back(Num(hi));
    anees_sum += a;
    ++anees_points;
    inside += a >= lo && a <= hi;
  }
  *average = anees_points ? anees_sum / anees_points : kNaN;
  *in_band_fraction = anees_points ? static_cast<double>(inside) / anees_points : kNaN;
  json out;
  out["step_s"] = Num(step);
  out["t"] = std::move(t);
  out["runs_with_nees"] = std::move(n);
  out["anees"] = std::move(anees);
  out["band_low"] = std::move(low);
  out["band_high"] = std::move(high);
  out["position_error_rms_m"] = std::move(err);
  out["position_sigma_rms_m"] = std::move(sigma);
  out["error_x_mean_m"] = std::move(ex);
  out["error_y_mean_m"] = std::move(ey);
  out["runs_with_error"] = std::move(err_n_series);
  for (int k = 0; k < 3; ++k) {
    out[std::string("error_rms_") + kAxes[k]] = std::move(axis_err[k]);
    out[std::string("sigma_rms_") + kAxes[k]] = std::move(axis_sigma[k]);
  }
  return out;
}

bool Compare(double measured, StudyExpectation::Op op, double value) {
  switch (op) {
    case StudyExpectation::Op::kLess:
      return measured < value;
    case StudyExpectation::Op::kLessEqual:
      return measured <= value;
    case StudyExpectation::Op::kGreater:
      return measured > value;
    case StudyExpectation::Op::kGreaterEqual:
      return measured >= value;
  }
  return false;
}

std::optional<double> JsonNumber(const json& object, const std::string& key) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number()) return std::nullopt;
  return it->get<double>();
}

}  // namespace

std::string OutcomeName(StudyRunRecord::Outcome outcome) {
  switch (outcome) {
    case StudyRunRecord::Outcome::kFinished:
      return "finished";
    case StudyRunRecord::Outcome::kFailed:
      return "failed";
    case StudyRunRecord::Outcome::kTimedOut:
      return "timed_out";
    case StudyRunRecord::Outcome::kNotRun:
      return "not_run";
  }
  return "not_run";
}

bool StudySummary::all_passed() const {
  return std::all_of(results.begin(), results.end(),
                     [](const StudyExpectationResult& r) { return r.passed; });
}

StudySummary SummarizeStudy(const StudySpec& spec, const std::vector<StudyRunRecord>& runs) {
  StudySummary summary;
  json& root = summary.json;
  root["schema_version"] = 1;
  root["runs_per_point"] = spec.runs;
  root["first_seed"] = spec.first_seed;
  root["vary"] = spec.vary_keys;
  root["pipelines"] = spec.pipelines;
  root["metrics"] = spec.metrics;
  root["divergence_nees"] = Num(spec.divergence_nees);
  root["may_diverge"] = spec.may_diverge;
  root["bootstrap"] = {{"resamples", study::kBootstrapResamples},
                       {"level", study::kConfidenceLevel},
                       {"method", "percentile bootstrap of the mean over seeds"}};

  summary.csv = "point";
  for (const std::string& key : spec.vary_keys) summary.csv += "," + key;
  summary.csv += ",pipeline,metric,n,mean,std,median,p95,min,max,ci_low,ci_high\n";
  summary.paired_csv = "point";
  for (const std::string& key : spec.vary_keys) summary.paired_csv += "," + key;
  summary.paired_csv +=
      ",a,b,metric,n,diff,diff_ci_low,diff_ci_high,ratio,ratio_ci_low,ratio_ci_high,a_lower,"
      "p_sign,p_wilcoxon\n";

  json points = json::array();
  int failed_total = 0;
  for (std::size_t p = 0; p < spec.points.size(); ++p) {
    const StudyPoint& point = spec.points[p];
    std::string csv_prefix = point.id;
    for (const auto& [key, value] : point.values) {
      const bool quote = value.find_first_of(",\"") != std::string::npos;
      std::string cell = value;
      if (quote) {
        cell.clear();
        for (char c : value) cell += c == '"' ? std::string("\"\"") : std::string(1, c);
        cell = "\"" + cell + "\"";
      }
      csv_prefix += "," + cell;
    }
    json runs_json;
    std::map<std::string, std::vector<std::uint64_t>> by_outcome;
    std::map<std::string, PipelineRuns> per_pipeline;
    for (const StudyRunRecord& run : runs) {
      if (run.point != p) continue;
      by_outcome[OutcomeName(run.outcome)].push_back(run.seed);
      if (run.outcome != StudyRunRecord::Outcome::kFinished) continue;
      const json metrics =
          json::parse(ReadRegularFile(run.folder / "metrics.json", kMaxMetricsBytes));
      for (const std::string& name : spec.pipelines) {
        PipelineRuns& pr = per_pipeline[name];
        const auto it = metrics.find("pipelines");
        if (it == metrics.end() || !it->contains(name)) {
          throw std::runtime_error((run.folder / "metrics.json").string() + ": no pipeline '" +
                                   name + "'");
        }
        const json& m = (*it)[name];
        pr.seeds.push_back(run.seed);
        for (const std::string& metric : spec.metrics) {
          if (const auto v = NumberAt(m, metric)) pr.values[metric][run.seed] = *v;
        }
        if (auto why = DivergedWhy(m, spec.divergence_nees)) {
          pr.diverged.push_back(run.seed);
          pr.diverged_why.push_back(std::move(*why));
        }
        if (m.contains("nis") && m["nis"].is_object()) {
          for (const auto& [type, n] : m["nis"].items()) {
            const auto count = NumberAt(n, "count");
            const auto mean = NumberAt(n, "mean");
            if (!count || !mean || *count <= 0) continue;
            PipelineRuns::Nis& pooled = pr.nis[type];
            pooled.count += *count;
            pooled.weighted_sum += *count * *mean;
            ++pooled.runs;
            const auto lo = NumberAt(n, "mean_band_low");
            const auto hi = NumberAt(n, "mean_band_high");
            pooled.runs_in_band += lo && hi && *mean >= *lo && *mean <= *hi;
            pooled.in_band_fraction_sum += NumberAt(n, "in_band_fraction").value_or(0.0);
          }
        }
        pr.series.push_back(ReadErrors(run.folder / (name + "_errors.csv")));
        ReadNis(run.folder / (name + "_nis.csv"), spec.time_step_s, &pr.nis_bins);
      }
    }
    for (const char* outcome : {"finished", "failed", "timed_out", "not_run"}) {
      runs_json[outcome] = by_outcome[outcome].size();
    }
    const int failed =
        static_cast<int>(by_outcome["failed"].size() + by_outcome["timed_out"].size());
    failed_total += failed;
    summary.not_run += static_cast<int>(by_outcome["not_run"].size());
    runs_json["failed_seeds"] = by_outcome["failed"];
    runs_json["timed_out_seeds"] = by_outcome["timed_out"];

    json pipelines_json;
    for (const std::string& name : spec.pipelines) {
      PipelineRuns& pr = per_pipeline[name];
      json pj;
      const bool may_diverge = std::find(spec.may_diverge.begin(), spec.may_diverge.end(), name) !=
                               spec.may_diverge.end();
      pj["runs"] = {{"finished", pr.seeds.size()},
                    {"diverged", pr.diverged.size()},
                    {"diverged_seeds", pr.diverged},
                    {"diverged_why", pr.diverged_why},
                    {"may_diverge", may_diverge}};
      for (std::size_t i = 0; i < pr.diverged.size(); ++i) {
        (may_diverge ? summary.allowed_divergences : summary.divergences)
            .push_back({point.id, name, pr.diverged[i], pr.diverged_why[i]});
      }
      json metrics_json, values_json;
      values_json["seed"] = pr.seeds;
      for (const std::string& metric : spec.metrics) {
        std::vector<double> values;
        json per_seed = json::array();
        for (std::uint64_t seed : pr.seeds) {
          const auto it = pr.values[metric].find(seed);
          if (it != pr.values[metric].end()) {
            values.push_back(it->second);
            per_seed.push_back(Num(it->second));
          } else {
            per_seed.push_back(nullptr);
          }
        }
        json d = Describe(values, point.id + "." + name + "." + metric);
        summary.csv += csv_prefix + "," + name + "," + metric + "," + std::to_string(values.size());
        for (const char* k : {"mean", "std", "median", "p95", "min", "max", "ci_low", "ci_high"}) {
          summary.csv += "," + (d[k].is_number() ? CsvNum(d[k].get<double>()) : std::string());
        }
        summary.csv += "\n";
        metrics_json[metric] = std::move(d);
        values_json[metric] = std::move(per_seed);
      }
      pj["metrics"] = std::move(metrics_json);
      double average = kNaN, in_band = kNaN;
      json series = SeriesJson(pr.series, spec.time_step_s, &average, &in_band);
      pj["nees"] = {{"dof", kPoseDof},
                    {"average", Num(average)},
                    {"in_band_fraction", Num(in_band)},
                    {"method",
                     "NEES averaged over the runs at each grid time, against the 95 % band of "
                     "the mean of N chi-square(3) values"}};
      json nis_json = json::object();
      for (const auto& [type, pooled] : pr.nis) {
        nis_json[type] = {
            {"count", pooled.count},
            {"mean", Num(pooled.weighted_sum / pooled.count)},
            {"runs", pooled.runs},
            {"runs_with_mean_in_band", pooled.runs_in_band},
            {"in_band_fraction_mean", Num(pooled.in_band_fraction_sum / pooled.runs)}};
      }
      AddNisSeries(pr.nis_bins, spec.time_step_s, &nis_json);
      pj["nis"] = std::move(nis_json);
      pj["series"] = std::move(series);
      pj["values"] = std::move(values_json);
      pipelines_json[name] = std::move(pj);
    }

    // Paired comparisons: every pair in scenario order, on the seeds both have a value for.
    json paired = json::array();
    for (std::size_t i = 0; i < spec.pipelines.size(); ++i) {
      for (std::size_t j = i + 1; j < spec.pipelines.size(); ++j) {
        const std::string& a = spec.pipelines[i];
        const std::string& b = spec.pipelines[j];
        json pair;
        pair["a"] = a;
        pair["b"] = b;
        json metrics_json;
        for (const std::string& metric : spec.metrics) {
          std::vector<double> va, vb, diff;
          int a_lower = 0;
          for (const auto& [seed, x] : per_pipeline[a].values[metric]) {
            const auto other = per_pipeline[b].values[metric].find(seed);
            if (other == per_pipeline[b].values[metric].end()) continue;
            va.push_back(x);
            vb.push_back(other->second);
            diff.push_back(x - other->second);
            a_lower += x < other->second;
          }
          json m;
          m["n"] = va.size();
          if (va.empty()) {
            for (const char* k : {"diff", "diff_ci_low", "diff_ci_high", "ratio", "ratio_ci_low",
                                  "ratio_ci_high", "a_lower", "p_sign", "p_wilcoxon"}) {
              m[k] = nullptr;
            }
          } else {
            const study::PairedIntervals ci = study::BootstrapPairedIntervals(
                va, vb, point.id + "." + a + "-" + b + "." + metric);
            const double mb = Mean(vb);
            m["diff"] = Num(Mean(diff));
            m["diff_ci_low"] = Num(ci.diff.low);
            m["diff_ci_high"] = Num(ci.diff.high);
            m["ratio"] = mb != 0.0 ? Num(Mean(va) / mb) : json(nullptr);
            m["ratio_ci_low"] = Num(ci.ratio.low);
            m["ratio_ci_high"] = Num(ci.ratio.high);
            m["a_lower"] = a_lower;
            m["p_sign"] = Num(study::SignTestP(diff));
            m["p_wilcoxon"] = Num(study::WilcoxonSignedRankP(diff));
          }
          summary.paired_csv +=
              csv_prefix + "," + a + "," + b + "," + metric + "," + std::to_string(va.size());
          for (const char* k : {"diff", "diff_ci_low", "diff_ci_high", "ratio", "ratio_ci_low",
                                "ratio_ci_high", "a_lower", "p_sign", "p_wilcoxon"}) {
            summary.paired_csv += "," + (m[k].is_number() ? CsvNum(m[k].get<double>()) : "");
          }
          summary.paired_csv += "\n";
          metrics_json[metric] = std::move(m);
        }
        pair["metrics"] = std::move(metrics_json);
        paired.push_back(std::move(pair));
      }
    }

    // The study's expectations at this point.
    json expectations = json::array();
    for (const StudyExpectation& e : spec.expectations) {
      StudyExpectationResult result;
      result.point = point.id;
      result.expectation = &e;
      switch (e.kind) {
        case StudyExpectation::Kind::kPipelineStat:
          result.measured = JsonNumber(pipelines_json[e.pipeline]["metrics"][e.metric], e.stat);
          break;
        case StudyExpectation::Kind::kNees:
          result.measured = JsonNumber(pipelines_json[e.pipeline]["nees"], e.stat);
          break;
        case StudyExpectation::Kind::kRuns:
          result.measured = JsonNumber(pipelines_json[e.pipeline]["runs"], e.stat);
          break;
        case StudyExpectation::Kind::kPaired:
          for (const json& pair : paired) {
            const bool forward = pair["a"] == e.pipeline && pair["b"] == e.other;
            const bool backward = pair["a"] == e.other && pair["b"] == e.pipeline;
            if (!forward && !backward) continue;
            const json& m = pair["metrics"][e.metric];
            if (forward) {
              result.measured = JsonNumber(m, e.stat);
            } else if (e.stat == "diff") {  // (b, a) asked for: swap the pair's sense
              if (auto v = JsonNumber(m, "diff")) result.measured = -*v;
            } else if (e.stat == "diff_ci_low") {
              if (auto v = JsonNumber(m, "diff_ci_high")) result.measured = -*v;
            } else if (e.stat == "diff_ci_high") {
              if (auto v = JsonNumber(m, "diff_ci_low")) result.measured = -*v;
            } else if (e.stat == "ratio") {
              if (auto v = JsonNumber(m, "ratio"); v && *v != 0.0) result.measured = 1.0 / *v;
            } else if (e.stat == "ratio_ci_low") {
              if (auto v = JsonNumber(m, "ratio_ci_high"); v && *v != 0.0)
                result.measured = 1.0 / *v;
            } else if (e.stat == "ratio_ci_high") {
              if (auto v = JsonNumber(m, "ratio_ci_low"); v && *v != 0.0)
                result.measured = 1.0 / *v;
            } else {
              result.measured = JsonNumber(m, e.stat);  // the tests' p-values are symmetric
            }
          }
          break;
        case StudyExpectation::Kind::kFailedRuns:
          result.measured = failed;
          break;
      }
      result.passed = result.measured && Compare(*result.measured, e.op, e.value);
      expectations.push_back({{"expectation", e.text},
                              {"measured", result.measured ? Num(*result.measured) : json(nullptr)},
                              {"passed", result.passed}});
      summary.results.push_back(result);
    }

    json pj;
    pj["id"] = point.id;
    json values = json::object();
    for (const auto& [key, value] : point.values) values[key] = value;
    pj["vary"] = std::move(values);
    pj["runs"] = std::move(runs_json);
    pj["pipelines"] = std::move(pipelines_json);
    pj["paired"] = std::move(paired);
    pj["expectations"] = std::move(expectations);
    points.push_back(std::move(pj));
  }
  summary.failed_runs = failed_total;
  root["points"] = std::move(points);
  root["all_expectations_passed"] = summary.all_passed();
  root["diverged_runs_failing"] = summary.divergences.size();
  return summary;
}

}  // namespace corridorsim
