#include "harness/study/study.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string_view>
#include <thread>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/installation.h"
#include "common/io/atomic_file.h"
#include "common/io/child_process.h"
#include "common/io/sha256.h"
#include "common/io/stable_json.h"
#include "harness/run/provenance.h"
#include "harness/run/run.h"
#include "harness/run/run_folder.h"
#include "harness/scenario/plugins.h"
#include "harness/study/study_file.h"
#include "harness/study/study_internal.h"
#include "harness/study/study_stats.h"
#include "harness/study/study_summary.h"

namespace corridorsim {

using namespace study_internal;

namespace study_internal {

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

namespace {
std::string SeedName(std::uint64_t seed) { return "seed_" + std::to_string(seed); }
}  // namespace

fs::path RunFolder(const fs::path& dir, const std::string& point, std::uint64_t seed) {
  return dir / "runs" / point / SeedName(seed);
}
fs::path StatusFile(const fs::path& dir, const std::string& point, std::uint64_t seed) {
  return dir / "status" / point / (SeedName(seed) + ".json");
}
fs::path LogFile(const fs::path& dir, const std::string& point, std::uint64_t seed) {
  return dir / "logs" / point / (SeedName(seed) + ".log");
}

}  // namespace study_internal

namespace {

constexpr const char* kMarker = StagedDirectory::kOutputFolderMarker;

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

// Prepares the study folder: new (created with its marker), the same study (resumed), or with
// --force an earlier corridorsim output (removed first). Anything else is bad input.
void PrepareFolder(const fs::path& dir, const std::string& plan_text, bool force,
                   const std::string& option) {
  const SourceLocation command_line{"command line", 0, 0};
  std::error_code error;
  if (fs::exists(dir, error) && !fs::is_directory(dir, error)) {
    throw InputError(command_line, option, "'" + dir.string() + "' is not a folder");
  }
  const bool empty = !fs::exists(dir, error) || fs::is_empty(dir, error);
  if (!empty) {
    const fs::path plan_file = dir / "study.json";
    const bool same = fs::is_regular_file(plan_file, error) &&
                      ReadRegularFile(plan_file, kMaxPlanBytes) == plan_text;
    if (same && !force) return;  // resumed
    if (!force) {
      throw InputError(command_line, option,
                       "'" + dir.string() +
                           (fs::exists(plan_file, error)
                                ? "' holds another study (its study.json differs: another "
                                  "scenario, sweep, seeds, expectations, may_diverge, build, "
                                  "plugin library or external program)"
                                : "' is not empty and holds no study") +
                           ": pass --force to start it over, or choose another folder");
    }
    if (!fs::exists(dir / kMarker, error)) {
      throw InputError(command_line, option,
                       "'" + dir.string() + "' was not written by corridorsim (no " + kMarker +
                           "): --force replaces only corridorsim's own folders");
    }
    fs::remove_all(dir, error);
    if (error) {
      throw InputError(command_line, option,
                       "cannot remove '" + dir.string() + "': " + error.message());
    }
  }
  fs::create_directories(dir, error);
  if (error) {
    throw InputError(command_line, option,
                     "cannot create '" + dir.string() + "': " + error.message());
  }
  EnsureWritableDirectory(dir);
  WriteFileAtomic(dir / kMarker, "");
  WriteFileAtomic(dir / "study.json", plan_text);
}

// Every planned run's outcome as the folder records it: finished when its run folder has
// metrics.json (run folders are committed whole), failed or timed out when its status says so.
std::vector<StudyRunRecord> CollectRecords(const StudySpec& spec, const fs::path& dir) {
  std::vector<StudyRunRecord> records;
  for (std::size_t p = 0; p < spec.points.size(); ++p) {
    for (int i = 0; i < spec.runs; ++i) {
      StudyRunRecord r;
      r.point = p;
      r.seed = spec.first_seed + static_cast<std::uint64_t>(i);
      r.folder = RunFolder(dir, spec.points[p].id, r.seed);
      std::error_code error;
      if (fs::is_regular_file(r.folder / "metrics.json", error)) {
        r.outcome = StudyRunRecord::Outcome::kFinished;
      } else if (const fs::path status = StatusFile(dir, spec.points[p].id, r.seed);
                 fs::is_regular_file(status, error)) {
        try {
          const json s = json::parse(ReadRegularFile(status, kMaxPlanBytes));
          const std::string outcome = s.at("outcome").get<std::string>();
          r.outcome = outcome == "timed_out" ? StudyRunRecord::Outcome::kTimedOut
                                             : StudyRunRecord::Outcome::kFailed;
          r.detail = s.value("detail", "");
        } catch (const std::exception&) {
          r.outcome = StudyRunRecord::Outcome::kFailed;
          r.detail = "an unreadable status file";
        }
      }
      records.push_back(std::move(r));
    }
  }
  return records;
}

std::string FormatDuration(double s) {
  char text[32];
  const long total = std::lround(std::max(0.0, s));
  if (total >= 3600) {
    std::snprintf(text, sizeof text, "%ldh%02ldm", total / 3600, (total % 3600) / 60);
  } else {
    std::snprintf(text, sizeof text, "%ldm%02lds", total / 60, total % 60);
  }
  return text;
}

std::string Fixed(const json& v, int decimals) {
  if (!v.is_number()) return "-";
  return FormatFixed(v.get<double>(), decimals);
}

// report.md: the numbers, the expectations and how they were made.
std::string ReportMarkdown(const StudySpec& spec, const StudySummary& summary,
                           const std::string& command, bool plots) {
  std::string md = "# Study report\n\n";
  md += "Made by `" + command + "` with corridorsim " + ProjectVersion() + ".\n\n";
  md += std::to_string(spec.points.size()) + " point(s) x " + std::to_string(spec.runs) +
        " run(s), seeds " + std::to_string(spec.first_seed) + " to " +
        std::to_string(spec.first_seed + static_cast<std::uint64_t>(spec.runs) - 1) +
        "; pipelines ";
  for (std::size_t i = 0; i < spec.pipelines.size(); ++i) {
    md += (i ? ", " : "") + ("`" + spec.pipelines[i] + "`");
  }
  md +=
      ". Intervals are 95 % percentile-bootstrap intervals of the mean over seeds; NEES is "
      "averaged over runs at each time and compared with the 95 % chi-square band of N runs "
      "(docs/studies.md).\n\n";
  for (const json& point : summary.json["points"]) {
    md += "## Point " + point["id"].get<std::string>();
    std::string values;
    for (const auto& [key, value] : point["vary"].items()) {
      values += (values.empty() ? "" : ", ") + key + " = " + value.get<std::string>();
    }
    md += values.empty() ? "\n\n" : " (" + values + ")\n\n";
    const json& runs = point["runs"];
    md += "Runs: " + std::to_string(runs["finished"].get<int>()) + " finished, " +
          std::to_string(runs["failed"].get<int>()) + " failed, " +
          std::to_string(runs["timed_out"].get<int>()) + " timed out, " +
          std::to_string(runs["not_run"].get<int>()) + " not run here.\n\n";
    md +=
        "| pipeline | ATE RMSE mean [95 % CI] (m) | median | p95 | RPE 1 m (m) | final error (m) "
        "| average NEES (in band) | diverged |\n|---|---|---|---|---|---|---|---|\n";
    for (const auto& [name, p] : point["pipelines"].items()) {
      const json& ate = p["metrics"]["ate_rmse_m"];
      md += "| `" + name + "` | " + Fixed(ate["mean"], 4) + " [" + Fixed(ate["ci_low"], 4) + ", " +
            Fixed(ate["ci_high"], 4) + "] | " + Fixed(ate["median"], 4) + " | " +
            Fixed(ate["p95"], 4) + " | " + Fixed(p["metrics"]["rpe_1m_trans_rmse_m"]["mean"], 4) +
            " | " + Fixed(p["metrics"]["final_position_error_m"]["mean"], 4) + " | " +
            Fixed(p["nees"]["average"], 2) + " (" + Fixed(p["nees"]["in_band_fraction"], 2) +
            ") | " + std::to_string(p["runs"]["diverged"].get<int>()) +
            (p["runs"]["may_diverge"].get<bool>() ? " (may diverge)" : "") + " |\n";
    }
    // Diverged runs that fail the study one per row; a may_diverge baseline's in one row.
    std::string diverged_rows;
    for (const auto& [name, p] : point["pipelines"].items()) {
      const json& seeds = p["runs"]["diverged_seeds"];
      if (seeds.empty()) continue;
      if (p["runs"]["may_diverge"].get<bool>()) {
        std::string list;
        for (const json& seed : seeds) list += (list.empty() ? "" : ", ") + seed.dump();
        diverged_rows += "| `" + name + "` | " + list + " | (" + std::to_string(seeds.size()) +
                         " runs) | no (may diverge) |\n";
        continue;
      }
      for (std::size_t i = 0; i < seeds.size(); ++i) {
        diverged_rows += "| `" + name + "` | " + seeds[i].dump() + " | " +
                         p["runs"]["diverged_why"][i].get<std::string>() + " | **yes** |\n";
      }
    }
    if (!diverged_rows.empty()) {
      md +=
          "\nDiverged runs (docs/studies.md, \"Failures\"):\n\n| pipeline | seed | why | fails the "
          "study |\n|---|---|---|---|\n" +
          diverged_rows;
    }
    std::string nis_rows;
    for (const auto& [name, p] : point["pipelines"].items()) {
      for (const auto& [type, n] : p["nis"].items()) {
        nis_rows += "| `" + name + "` | " + type + " | " + Fixed(n["count"], 0) + " | " +
                    Fixed(n["mean"], 3) + " | " + Fixed(n.value("time_average", json()), 3) +
                    " | " + Fixed(n.value("time_in_band_fraction", json()), 2) + " |\n";
      }
    }
    if (!nis_rows.empty()) {
      md +=
          "\nNIS per landmark type (applied updates of all runs; over time: pooled per time bin "
          "against the band of their mean):\n\n| pipeline | landmark type | updates | mean NIS "
          "| mean over time | time in band |\n|---|---|---|---|---|---|\n" +
          nis_rows;
    }
    md +=
        "\nPaired on the same seeds (ATE RMSE, a - b):\n\n| a | b | n | mean difference [95 % CI] "
        "(m) | ratio of means [95 % CI] | a lower | sign test p | Wilcoxon p |\n"
        "|---|---|---|---|---|---|---|---|\n";
    for (const json& pair : point["paired"]) {
      const json& m = pair["metrics"]["ate_rmse_m"];
      md += "| `" + pair["a"].get<std::string>() + "` | `" + pair["b"].get<std::string>() + "` | " +
            std::to_string(m["n"].get<int>()) + " | " + Fixed(m["diff"], 4) + " [" +
            Fixed(m["diff_ci_low"], 4) + ", " + Fixed(m["diff_ci_high"], 4) + "] | " +
            Fixed(m["ratio"], 3) + " [" + Fixed(m["ratio_ci_low"], 3) + ", " +
            Fixed(m["ratio_ci_high"], 3) + "] | " +
            (m["a_lower"].is_number() ? std::to_string(m["a_lower"].get<int>()) : "-") + " | " +
            Fixed(m["p_sign"], 4) + " | " + Fixed(m["p_wilcoxon"], 4) + " |\n";
    }
    if (!point["expectations"].empty()) {
      md += "\n| expectation | measured | result |\n|---|---|---|\n";
      for (const json& e : point["expectations"]) {
        md += "| `" + e["expectation"].get<std::string>() + "` | " + Fixed(e["measured"], 6) +
              " | " + (e["passed"].get<bool>() ? "passed" : "**FAILED**") + " |\n";
      }
    }
    md += "\n";
  }
  if (plots) {
    md +=
        "## Plots\n\n![ATE per pipeline](plots/ate_box.png)\n\n"
        "![Position error over time](plots/error_over_time.png)\n\n"
        "![Error per axis (x, y, yaw) over time](plots/error_axes.png)\n\n"
        "![NEES over time](plots/nees.png)\n\n";
    if (!spec.vary_keys.empty()) md += "![Sweep](plots/sweep.png)\n\n";
    bool any_nis = false;  // plot_study.py draws the first point's NIS
    for (const auto& [name, p] : summary.json["points"][0]["pipelines"].items()) {
      any_nis = any_nis || !p["nis"].empty();
    }
    if (any_nis) md += "![NIS per landmark type over time](plots/nis_over_time.png)\n\n";
  }
  md +=
      "Files: summary.json (everything above, with the per-run values and the series), "
      "summary.csv, paired.csv, runs/<point>/seed_<N>/ (each a `corridorsim run` folder), "
      "points/<point>.yaml (each point's scenario), timing.json (wall clock, memory).\n";
  return md;
}

std::string CommandText(const StudyRequest& request) {
  std::string text = "corridorsim study";
  if (!request.merge_dirs.empty()) {
    text += " merge";
    for (const fs::path& d : request.merge_dirs) text += " " + d.string();
  } else {
    text += " " + request.scenario_file;
    if (request.runs) text += " --runs " + std::to_string(*request.runs);
    if (request.seed) text += " --seed " + std::to_string(*request.seed);
    text += MayDivergeArgument(request);
    for (const std::string& setting : request.settings) text += " --set " + setting;
    if (request.shard_count > 1) {
      text += " --shard " + std::to_string(request.shard_index + 1) + "/" +
              std::to_string(request.shard_count);
    }
  }
  return text + " --out " + request.out_dir.string();
}

std::optional<std::string> MakeStudyPlots(const fs::path& dir) {
  std::optional<std::string> error = RunPlotScript("plot_study.py", {dir.string()});
  if (const int signal = StopSignal()) DieOfSignal(signal);  // forwarded to python3, which ended
  return error;
}

// P1 Fig. 16 over a study: the frame costs of the runs' maps/<pipeline>_frame_times.csv (the
// pipelines that write one), binned by the landmarks in the state. Wall clock, so not part of
// the deterministic summary: frame_times.csv beside timing.json. Returns false when no run has
// such a file (nothing written).
bool WriteFrameTimes(const StudySpec& spec, const std::vector<StudyRunRecord>& records,
                     const fs::path& dir) {
  constexpr int kBin = 10;  // landmarks per bin
  std::string csv = "point,pipeline,landmarks_low,landmarks_high,frames,mean_ms,median_ms,p95_ms\n";
  bool any = false;
  for (std::size_t p = 0; p < spec.points.size(); ++p) {
    for (const std::string& name : spec.pipelines) {
      std::map<int, std::vector<double>> bins;
      for (const StudyRunRecord& r : records) {
        if (r.point != p || r.outcome != StudyRunRecord::Outcome::kFinished) continue;
        const fs::path file = r.folder / "maps" / (name + "_frame_times.csv");
        std::error_code error;
        if (!fs::is_regular_file(file, error)) continue;
        std::string text;
        try {
          text = ReadRegularFile(file, std::uint64_t{256} << 20);
        } catch (const std::exception&) {
          continue;
        }
        std::size_t pos = text.find('\n');
        while (pos != std::string::npos && pos + 1 < text.size()) {
          const std::size_t end = std::min(text.find('\n', pos + 1), text.size());
          double stamp = 0.0, ms = 0.0;
          int landmarks = 0;
          if (std::sscanf(text.c_str() + pos + 1, "%lf,%d,%lf", &stamp, &landmarks, &ms) == 3 &&
              landmarks >= 0 && std::isfinite(ms)) {
            bins[landmarks / kBin].push_back(ms);
          }
          pos = end;
        }
      }
      for (const auto& [bin, values] : bins) {
        any = true;
        double sum = 0.0;
        for (double v : values) sum += v;
        csv += spec.points[p].id + "," + name + "," + std::to_string(bin * kBin) + "," +
               std::to_string(bin * kBin + kBin - 1) + "," + std::to_string(values.size()) + "," +
               FormatFixed(sum / static_cast<double>(values.size()), 3) + "," +
               FormatFixed(study::Quantile(values, 0.5), 3) + "," +
               FormatFixed(study::Quantile(values, 0.95), 3) + "\n";
      }
    }
  }
  if (any) WriteFileAtomic(dir / "frame_times.csv", csv);
  return any;
}

void PrintDivergences(const std::vector<StudyDivergence>& list, const fs::path& dir) {
  for (const StudyDivergence& d : list) {
    std::printf("  %s seed %llu: %s diverged: %s (run: %s)\n", d.point.c_str(),
                static_cast<unsigned long long>(d.seed), d.pipeline.c_str(), d.why.c_str(),
                RunFolder(dir, d.point, d.seed).string().c_str());
  }
}

// Writes the summary files, the report and the plots; prints the closing table. Returns the
// exit code.
int FinishStudy(const StudySpec& spec, const fs::path& dir, const StudyRequest& request,
                json timing) {
  const Clock::time_point start = Clock::now();
  // Stop signals are caught since the runs started (CatchStopSignals): each stage ends the
  // study as the signal would, before the next (the runs' results stay; the command resumes).
  const auto stop_here = [] {
    if (const int signal = StopSignal()) DieOfSignal(signal);
  };
  stop_here();
  const std::vector<StudyRunRecord> records = CollectRecords(spec, dir);
  stop_here();
  const StudySummary summary = SummarizeStudy(spec, records);
  stop_here();
  WriteFileAtomic(dir / "summary.json", JsonFileText(summary.json));
  WriteFileAtomic(dir / "summary.csv", summary.csv);
  WriteFileAtomic(dir / "paired.csv", summary.paired_csv);
  WriteFileAtomic(dir / "report.md",
                  ReportMarkdown(spec, summary, CommandText(request), request.plots));
  if (WriteFrameTimes(spec, records, dir)) timing["frame_times"] = "frame_times.csv";
  timing["summary_seconds"] = Seconds(start);
  std::optional<std::string> plot_error;
  if (request.plots) {
    const Clock::time_point t_plots = Clock::now();
    plot_error = MakeStudyPlots(dir);
    timing["plot_seconds"] = Seconds(t_plots);
  }
  std::optional<std::string> report_error;
  if (request.viewer) {
    // report.html (docs/viewer.md): the study's figures and runs, linking each run's viewer.
    const Clock::time_point t_report = Clock::now();
    report_error = RunPlotScript("make_report.py", {dir.string()});
    stop_here();  // forwarded to python3, which ended
    timing["report_seconds"] = Seconds(t_report);
  }
  RoundNumbers(timing, json_steps::kSeconds);
  WriteFileAtomic(dir / "timing.json", JsonFileText(timing));

  std::printf("\nstudy: %zu point(s) x %d seed(s)\n", spec.points.size(), spec.runs);
  for (const json& point : summary.json["points"]) {
    std::printf("%s:", point["id"].get<std::string>().c_str());
    for (const auto& [key, value] : point["vary"].items()) {
      std::printf(" %s=%s", key.c_str(), value.get<std::string>().c_str());
    }
    std::printf(" (%d finished)\n", point["runs"]["finished"].get<int>());
    for (const auto& [name, p] : point["pipelines"].items()) {
      const json& ate = p["metrics"]["ate_rmse_m"];
      std::printf("  %-20s ATE RMSE mean %s m [%s, %s], median %s, NEES %s, diverged %d\n",
                  name.c_str(), Fixed(ate["mean"], 4).c_str(), Fixed(ate["ci_low"], 4).c_str(),
                  Fixed(ate["ci_high"], 4).c_str(), Fixed(ate["median"], 4).c_str(),
                  Fixed(p["nees"]["average"], 2).c_str(), p["runs"]["diverged"].get<int>());
    }
  }
  for (const StudyExpectationResult& r : summary.results) {
    std::printf("%s %s: %s (measured %s)\n", r.passed ? "passed" : "FAILED", r.point.c_str(),
                r.expectation->text.c_str(),
                r.measured ? FormatFixed(*r.measured, 6).c_str() : "nothing");
  }
  std::printf(
      "wrote %s/{study.json, summary.json, summary.csv, paired.csv, report.md, "
      "timing.json%s%s, runs/, points/}\n",
      dir.string().c_str(), plot_error || !request.plots ? "" : ", plots/",
      report_error || !request.viewer ? "" : ", report.html");
  int code = 0;
  if (summary.failed_runs > 0) {
    std::printf("study: %d run(s) failed or timed out:\n", summary.failed_runs);
    for (const StudyRunRecord& r : records) {
      if (r.outcome != StudyRunRecord::Outcome::kFailed &&
          r.outcome != StudyRunRecord::Outcome::kTimedOut) {
        continue;
      }
      std::printf("  %s seed %llu: %s (log: %s)\n", spec.points[r.point].id.c_str(),
                  static_cast<unsigned long long>(r.seed), r.detail.c_str(),
                  LogFile(dir, spec.points[r.point].id, r.seed).string().c_str());
    }
    code = 1;
  }
  if (!summary.allowed_divergences.empty()) {
    // Expected (baselines): one line per point and pipeline, the seeds only.
    std::printf(
        "study: %zu run(s) of pipelines that may diverge (baselines, study.may_diverge) "
        "diverged:",
        summary.allowed_divergences.size());
    const StudyDivergence* last = nullptr;
    for (const StudyDivergence& d : summary.allowed_divergences) {
      const bool first = !last || last->point != d.point || last->pipeline != d.pipeline;
      if (first) std::printf("\n  %s %s: seeds", d.point.c_str(), d.pipeline.c_str());
      std::printf("%s %llu", first ? "" : ",", static_cast<unsigned long long>(d.seed));
      last = &d;
    }
    std::printf("\n");
  }
  if (!summary.divergences.empty()) {
    std::printf(
        "study: %zu run(s) diverged (a pipeline that is expected to is marked `baseline: true` "
        "in the scenario's pipelines, or goes in study.may_diverge or --may-diverge):\n",
        summary.divergences.size());
    PrintDivergences(summary.divergences, dir);
    code = 1;
  }
  if (code == 0 && !summary.all_passed()) {
    code = 3;
  } else if (code == 0 && (plot_error || report_error)) {
    code = 4;
  }
  if (plot_error)
    std::fprintf(stderr, "corridorsim: warning: plots/ failed: %s\n", plot_error->c_str());
  if (report_error)
    std::fprintf(stderr, "corridorsim: warning: report.html failed: %s\n", report_error->c_str());
  if (request.shard_count > 1 && code != 0) {
    // A shard holds part of the runs: its expectations and failures are judged by `study merge`
    // (a Slurm merge job runs only after every task exited 0: --dependency=afterok).
    std::printf(
        "study: shard %d/%d done; the study's verdict (exit %d here) is given by `study "
        "merge`\n",
        request.shard_index + 1, request.shard_count, code);
    code = 0;
  }
  if (summary.not_run > 0) {
    std::printf(
        "note: %d run(s) of the plan are not in this folder (other shards; `corridorsim "
        "study merge` combines them)\n",
        summary.not_run);
  }
  return code;
}

}  // namespace

namespace study_internal {

// " --may-diverge a,b" as given, or "" (PrepareStudy has checked each name against the study's
// pipelines, whose names are [a-z0-9_] words: no quoting needed).
std::string MayDivergeArgument(const StudyRequest& request) {
  std::string names;
  for (const std::string& name : request.may_diverge) names += (names.empty() ? "" : ",") + name;
  return names.empty() ? "" : " --may-diverge " + names;
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

// Starts one run: `corridorsim run <point scenario> --seed S --out runs/<point>/seed_S`.
// `viewer`: false adds --no-viewer.
std::unique_ptr<ChildProcess> StartRun(const std::string& program, const StudySpec& spec,
                                       const fs::path& dir, const PlannedRun& run, bool viewer) {
  const std::string& id = spec.points[run.point].id;
  std::error_code error;
  fs::create_directories(RunFolder(dir, id, run.seed).parent_path(), error);
  fs::create_directories(LogFile(dir, id, run.seed).parent_path(), error);
  fs::create_directories(StatusFile(dir, id, run.seed).parent_path(), error);
  fs::remove(StatusFile(dir, id, run.seed), error);
  std::vector<std::string> argv = {program,
                                   "run",
                                   (dir / "points" / (id + ".yaml")).string(),
                                   "--seed",
                                   std::to_string(run.seed),
                                   "--out",
                                   RunFolder(dir, id, run.seed).string(),
                                   "--force",
                                   "--no-plots"};
  if (!viewer) argv.push_back("--no-viewer");
  return std::make_unique<ChildProcess>(argv, LogFile(dir, id, run.seed).string());
}

// How a run ended, recorded in status/<point>/seed_<S>.json (and returned).
json RecordRun(const StudySpec& spec, const fs::path& dir, const PlannedRun& run,
               const ChildStatus& status, bool timed_out, double elapsed, double peak_rss_mib) {
  const std::string& id = spec.points[run.point].id;
  const fs::path folder = RunFolder(dir, id, run.seed);
  std::error_code error;
  const bool results = fs::is_regular_file(folder / "metrics.json", error);
  // 3 (a scenario expectation failed), 4 (an extra failed) and 5 (a pipeline failed: the summary
  // counts it among its pipeline's diverged runs) are results too.
  const bool finished = !timed_out && status.started && status.signal == 0 &&
                        RunWroteResults(status.exit_code) && results;
  const std::string outcome = finished ? "finished" : timed_out ? "timed_out" : "failed";
  const std::string detail =
      timed_out ? "timed out after " + FormatFixed(spec.run_timeout_s, 0) + " s"
                : DescribeChildStatus(status) +
                      (status.exit_code == 0 && !results ? " without metrics.json" : "");
  if (!finished && results) {
    fs::remove_all(folder, error);  // a timed-out run that committed: not a result
  }
  json record = {{"point", id},
                 {"seed", run.seed},
                 {"outcome", outcome},
                 {"detail", detail},
                 {"exit_code", status.exit_code},
                 {"signal", status.signal},
                 {"wall_seconds", elapsed},
                 {"peak_rss_mib", peak_rss_mib}};
  WriteFileAtomic(StatusFile(dir, id, run.seed), JsonFileText(record));
  return record;
}

}  // namespace study_internal

int RunStudy(const StudyRequest& request) {
  if (request.slurm) return WriteSlurmStudy(request);
  const Clock::time_point study_start = Clock::now();
  const PreparedStudy prepared = PrepareStudy(request);
  const StudySpec& spec = prepared.spec;
  const fs::path& dir = prepared.dir;
  const std::vector<PlannedRun>& todo = prepared.todo;
  const std::size_t planned_here = prepared.planned_here, already = prepared.already;

  std::map<std::string, std::pair<double, int>> ate;  // running mean ATE per pipeline
  const auto add_ate = [&](const fs::path& folder) {
    try {
      const json m = json::parse(ReadRegularFile(folder / "metrics.json", kMaxPlanBytes));
      for (const std::string& name : spec.pipelines) {
        const json& v = m["pipelines"][name]["ate_rmse_m"];
        if (v.is_number()) {
          ate[name].first += v.get<double>();
          ++ate[name].second;
        }
      }
    } catch (const std::exception&) {
      // the summary reports a damaged folder; progress only skips it
    }
  };
  for (const StudyRunRecord& r : CollectRecords(spec, dir)) {
    if (r.outcome == StudyRunRecord::Outcome::kFinished) add_ate(r.folder);
  }
  int jobs = request.jobs > 0 ? request.jobs
                              : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  jobs = std::min(jobs, kMaxStudyJobs);
  const std::string program = request.run_program.empty() ? ThisProgram() : request.run_program;
  std::printf(
      "study: %s, %zu point(s) x %d seed(s) = %zu run(s)%s; %zu already finished, %zu "
      "to run, %d worker(s); folder %s\n",
      request.scenario_file.c_str(), spec.points.size(), spec.runs,
      spec.points.size() * static_cast<std::size_t>(spec.runs),
      request.shard_count > 1
          ? (", shard " + std::to_string(request.shard_index + 1) + "/" +
             std::to_string(request.shard_count) + ": " + std::to_string(planned_here))
                .c_str()
          : "",
      already, todo.size(), jobs, dir.string().c_str());
  std::fflush(stdout);

  struct Active {
    PlannedRun run;
    std::unique_ptr<ChildProcess> child;
    Clock::time_point start;
    bool timed_out = false;
  };
  std::vector<Active> active;
  std::size_t next = 0, done = 0;
  int failed = 0;
  double run_seconds_sum = 0.0, peak_rss_mib = 0.0;
  json run_timing = json::array();
  const Clock::time_point loop_start = Clock::now();
  CatchStopSignals();
  while (next < todo.size() || !active.empty()) {
    if (const int signal = StopSignal()) {
      // Stopped (Ctrl-C, kill): the runs in flight are stopped too and waited for, so that none
      // commits after the study has ended; they run again when the study is resumed.
      for (Active& a : active) a.child->Signal(signal);
      for (Active& a : active) a.child->Wait();
      std::fprintf(stderr,
                   "corridorsim: study stopped by signal %d (%s) with %zu run(s) in flight, "
                   "stopped too; %zu of %zu run(s) of this folder finished: the same command "
                   "resumes it\n",
                   signal, ::strsignal(signal), active.size(), done + already, planned_here);
      DieOfSignal(signal);
    }
    while (static_cast<int>(active.size()) < jobs && next < todo.size()) {
      const PlannedRun& t = todo[next++];
      active.push_back({t, StartRun(program, spec, dir, t, request.viewer), Clock::now()});
    }
    bool changed = false;
    for (auto it = active.begin(); it != active.end();) {
      const double elapsed = Seconds(it->start);
      if (!it->timed_out && elapsed > spec.run_timeout_s) {
        it->child->Kill();
        it->timed_out = true;
      }
      const std::optional<ChildStatus> status = it->child->Poll();
      if (!status) {
        ++it;
        continue;
      }
      // Stopping (Ctrl-C reaches the runs of a terminal's process group too): a run that ended
      // now is not recorded as failed; the stop above waits for it.
      if (StopSignal() != 0) break;
      const std::string& id = spec.points[it->run.point].id;
      json record =
          RecordRun(spec, dir, it->run, *status, it->timed_out, elapsed, it->child->peak_rss_mib());
      const bool finished = record["outcome"] == "finished";
      const std::string detail = record["detail"].get<std::string>();
      run_timing.push_back(std::move(record));
      ++done;
      run_seconds_sum += elapsed;
      peak_rss_mib = std::max(peak_rss_mib, it->child->peak_rss_mib());
      if (finished) {
        add_ate(RunFolder(dir, id, it->run.seed));
      } else {
        ++failed;
      }
      const double per_run = run_seconds_sum / static_cast<double>(done);
      const std::size_t left = todo.size() - done;
      std::string means;
      for (const std::string& name : spec.pipelines) {
        if (ate[name].second == 0) continue;
        means += " " + name + " " + FormatFixed(ate[name].first / ate[name].second, 4);
      }
      std::printf(
          "study: [%zu/%zu] %s seed %llu %s in %.0f s; %zu running, %d failed, ETA %s; "
          "mean ATE (m):%s\n",
          done + already, planned_here, id.c_str(), static_cast<unsigned long long>(it->run.seed),
          finished ? "finished" : detail.c_str(), elapsed, active.size() - 1, failed,
          FormatDuration(per_run * static_cast<double>(left) /
                         std::max(1, std::min<int>(jobs, static_cast<int>(left + 1))))
              .c_str(),
          means.c_str());
      std::fflush(stdout);
      it = active.erase(it);
      changed = true;
    }
    if (!changed) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  const double loop_seconds = Seconds(loop_start);
  json timing;
  timing["jobs"] = jobs;
  timing["runs_executed"] = done;
  timing["runs_already_finished"] = already;
  timing["wall_seconds_before_runs"] =
      std::chrono::duration<double>(loop_start - study_start).count();
  timing["runs_wall_seconds"] = loop_seconds;
  timing["run_seconds_sum"] = run_seconds_sum;
  timing["throughput_runs_per_hour"] =
      loop_seconds > 0 ? 3600.0 * static_cast<double>(done) / loop_seconds : 0.0;
  timing["peak_rss_mib_max"] = peak_rss_mib;
  timing["runs"] = std::move(run_timing);
  return FinishStudy(spec, dir, request, std::move(timing));
}

namespace {

// True when `status` records a run that failed or timed out (a status that says "finished"
// stands for a run folder, which must be there).
bool RecordedFailure(const fs::path& status) {
  std::error_code error;
  if (!fs::is_regular_file(status, error)) return false;
  try {
    return json::parse(ReadRegularFile(status, kMaxPlanBytes)).value("outcome", "") != "finished";
  } catch (const std::exception&) {
    return true;  // unreadable: recorded as a failure (CollectRecords)
  }
}

// Every run of the plan must be in one of the folders to merge (finished, or recorded as failed
// or timed out), or already in the output folder of a resumed merge: a merge that lacks runs (a
// shard not given, or one that has not ended) would summarise part of the study and judge its
// expectations on that part. Refused as incomplete input (exit 2), naming the missing runs and,
// when the folders are shards, the shards they belong to.
void RequireCompleteMerge(const StudySpec& spec, const StudyRequest& request,
                          const std::string& plan_text) {
  constexpr std::size_t kListed = 12;  // runs and shards named in the message
  std::vector<fs::path> sources = request.merge_dirs;
  std::error_code error;
  const fs::path out_plan = request.out_dir / "study.json";
  if (!request.force && fs::is_regular_file(out_plan, error) &&
      ReadRegularFile(out_plan, kMaxPlanBytes) == plan_text) {
    sources.push_back(request.out_dir);
  }
  long shards = 0;  // N of the folders' --shard K/N, when they say so alike
  for (const fs::path& d : request.merge_dirs) {
    try {
      const json shard = json::parse(ReadRegularFile(d / "shard.json", kMaxPlanBytes));
      const long of = shard.at("of").get<long>();
      shards = shards == 0 || shards == of ? of : -1;
    } catch (const std::exception&) {
      // not a shard (a whole or resumed study folder)
    }
  }
  long missing = 0, index = 0;
  std::string runs;
  std::set<long> missing_shards;
  for (const StudyPoint& point : spec.points) {
    for (int i = 0; i < spec.runs; ++i, ++index) {
      const std::uint64_t seed = spec.first_seed + static_cast<std::uint64_t>(i);
      const bool found = std::any_of(sources.begin(), sources.end(), [&](const fs::path& d) {
        return fs::is_regular_file(RunFolder(d, point.id, seed) / "metrics.json", error) ||
               RecordedFailure(StatusFile(d, point.id, seed));
      });
      if (found) continue;
      if (++missing <= static_cast<long>(kListed)) {
        runs += (runs.empty() ? "" : ", ") + point.id + " seed " + std::to_string(seed);
      }
      if (shards > 0) missing_shards.insert(index % shards + 1);
    }
  }
  if (missing == 0) return;
  std::string message = std::to_string(missing) + " of the plan's " + std::to_string(index) +
                        " run(s) are in none of the folders (" + runs +
                        (missing > static_cast<long>(kListed) ? ", ..." : "") + ")";
  if (!missing_shards.empty()) {
    std::string list;
    std::size_t listed = 0;
    for (const long k : missing_shards) {
      if (++listed > kListed) {
        list += ", ...";
        break;
      }
      list += (list.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(shards);
    }
    message += "; missing from shard(s) " + list;
  }
  throw InputError(SourceLocation{"command line", 0, 0}, "DIR",
                   message +
                       ": the merge is incomplete; merge every shard, each once it has ended "
                       "(a shard resumes with its own command)");
}

}  // namespace

int MergeStudies(const StudyRequest& request) {
  const SourceLocation command_line{"command line", 0, 0};
  if (request.merge_dirs.empty()) throw InputError(command_line, "DIR", "no study folder given");
  std::string plan_text;
  for (const fs::path& d : request.merge_dirs) {
    const fs::path plan_file = d / "study.json";
    std::error_code error;
    if (!fs::is_regular_file(plan_file, error)) {
      throw InputError(command_line, "DIR", "'" + d.string() + "' holds no study.json");
    }
    const std::string text = ReadRegularFile(plan_file, kMaxPlanBytes);
    if (plan_text.empty()) {
      plan_text = text;
    } else if (text != plan_text) {
      std::string why = "the plans differ";
      try {
        const std::string plugins = PluginDifference(json::parse(plan_text), json::parse(text));
        if (!plugins.empty()) why = plugins;
      } catch (const json::exception&) {
        // not JSON: "the plans differ" says enough
      }
      throw InputError(SourceLocation{plan_file.string(), 0, 0}, "",
                       "another study than " + (request.merge_dirs[0] / "study.json").string() +
                           " (" + why + ")");
    }
  }
  // The output folder is none of the folders merged and lies inside none; it holds one only as
  // the --slurm layout does, under its shards/ (never removed: --force is refused below).
  std::vector<JobInput> inputs;
  for (const fs::path& d : request.merge_dirs) {
    if (!PathWithin(d, request.out_dir / "shards")) inputs.push_back({d, "a folder to merge"});
  }
  RefuseOutputOverInputs(request.out_dir, "--out", inputs);
  const fs::path first_plan = request.merge_dirs[0] / "study.json";
  const json plan = ReadPlan(first_plan);
  const StudySpec spec = SpecFromPlan(plan, first_plan);
  // The points' scenarios, read (and checked against the plan's hashes) before anything is
  // written.
  std::vector<std::string> point_yaml;
  for (std::size_t i = 0; i < spec.points.size(); ++i) {
    const fs::path from = request.merge_dirs[0] / "points" / (spec.points[i].id + ".yaml");
    point_yaml.push_back(ReadRegularFile(from, kMaxPlanBytes));
    if (Sha256Hex(point_yaml.back()) != plan["points"][i].value("scenario_sha256", "")) {
      throw InputError(
          SourceLocation{from.string(), 0, 0}, "",
          "not the scenario of the plan (its SHA-256 differs from " + first_plan.string() + "'s)");
    }
  }
  const fs::path dir = request.out_dir;
  std::error_code error;
  const fs::path out_abs = fs::weakly_canonical(dir, error);
  if (request.force) {
    // --force removes the output folder first: never while it holds a folder to merge (the
    // layout of --slurm merges <study>/shards/K into <study>; that merge resumes, no --force).
    for (const fs::path& d : request.merge_dirs) {
      const fs::path inside = fs::weakly_canonical(d, error).lexically_relative(out_abs);
      if (!inside.empty() && *inside.begin() != "..") {
        throw InputError(command_line, "--force",
                         "'" + InputExcerpt(dir.string()) + "' holds '" + InputExcerpt(d.string()) +
                             "', a folder to merge, which --force would remove before it is read");
      }
    }
  }
  RequireCompleteMerge(spec, request, plan_text);
  PrepareFolder(dir, plan_text, request.force, "--out");
  fs::create_directories(dir / "points", error);
  for (std::size_t i = 0; i < spec.points.size(); ++i) {
    WriteFileAtomic(dir / "points" / (spec.points[i].id + ".yaml"), point_yaml[i]);
  }
  // Each run from the first folder that finished it, else the first that recorded a failure
  // (RequireCompleteMerge has made sure that one of them does).
  int copied = 0;
  for (const StudyPoint& point : spec.points) {
    for (int i = 0; i < spec.runs; ++i) {
      const std::uint64_t seed = spec.first_seed + static_cast<std::uint64_t>(i);
      const fs::path target = RunFolder(dir, point.id, seed);
      if (fs::is_regular_file(target / "metrics.json", error)) continue;  // resumed merge
      const auto finished = std::find_if(
          request.merge_dirs.begin(), request.merge_dirs.end(), [&](const fs::path& d) {
            return fs::is_regular_file(RunFolder(d, point.id, seed) / "metrics.json", error);
          });
      if (finished != request.merge_dirs.end()) {
        const fs::path source = RunFolder(*finished, point.id, seed);
        const fs::path staging = target.string() + ".merging";
        fs::remove_all(staging, error);
        fs::create_directories(staging.parent_path(), error);
        // Links are copied as links: a link in a folder to merge is never followed (one to "/"
        // would copy the file system).
        fs::copy(source, staging, fs::copy_options::recursive | fs::copy_options::copy_symlinks,
                 error);
        if (error) {
          throw std::runtime_error("cannot copy '" + source.string() + "': " + error.message());
        }
        fs::remove_all(target, error);  // an unfinished leftover of a resumed merge
        fs::rename(staging, target, error);
        if (error) {
          throw std::runtime_error("cannot move '" + staging.string() + "' to '" + target.string() +
                                   "': " + error.message());
        }
        ++copied;
        continue;
      }
      for (const fs::path& d : request.merge_dirs) {
        const fs::path status = StatusFile(d, point.id, seed);
        if (RecordedFailure(status)) {
          fs::create_directories(StatusFile(dir, point.id, seed).parent_path(), error);
          WriteFileAtomic(StatusFile(dir, point.id, seed), ReadRegularFile(status, kMaxPlanBytes));
          break;
        }
      }
    }
  }
  std::printf("study merge: %zu folder(s), %d run folder(s) copied into %s\n",
              request.merge_dirs.size(), copied, dir.string().c_str());
  json timing;
  timing["merged_folders"] = request.merge_dirs.size();
  timing["runs_copied"] = copied;
  return FinishStudy(spec, dir, request, std::move(timing));
}

}  // namespace corridorsim
