// The end of a study or a merge, from the runs its folder holds: summary.json, summary.csv,
// paired.csv, report.md, frame_times.csv, plots/, report.html and timing.json; the closing table
// and the exit code (study.h).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/io/atomic_file.h"
#include "common/io/child_process.h"
#include "common/io/stable_json.h"
#include "harness/run/provenance.h"
#include "harness/run/run_folder.h"
#include "harness/study/study.h"
#include "harness/study/study_file.h"
#include "harness/study/study_internal.h"
#include "harness/study/study_stats.h"
#include "harness/study/study_summary.h"

namespace corridorsim::study_internal {

// " --may-diverge a,b" as given, or "" (PrepareStudy has checked each name against the study's
// pipelines, whose names are [a-z0-9_] words: no quoting needed).
std::string MayDivergeArgument(const StudyRequest& request) {
  std::string names;
  for (const std::string& name : request.may_diverge) names += (names.empty() ? "" : ",") + name;
  return names.empty() ? "" : " --may-diverge " + names;
}

namespace {

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

}  // namespace

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

}  // namespace corridorsim::study_internal
