// `corridorsim study` (RunStudy): the runs of this shard, each a `corridorsim run` child process,
// J at a time, with their progress, timeouts and stop signals; how each run ended (its status
// file); then the summary (study_finish.cpp).

#include "harness/study/study.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/io/atomic_file.h"
#include "common/io/child_process.h"
#include "common/io/stable_json.h"
#include "harness/run/run.h"
#include "harness/run/run_folder.h"
#include "harness/study/study_file.h"
#include "harness/study/study_internal.h"
#include "harness/study/study_summary.h"

namespace corridorsim {

using namespace study_internal;

namespace study_internal {

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// Starts one run: `corridorsim run <point scenario> --seed S --out runs/<point>/seed_S`, or
// `corridorsim replay <recording> <point scenario> ...`. `viewer`: false adds --no-viewer.
std::unique_ptr<ChildProcess> StartRun(const std::string& program, const StudySpec& spec,
                                       const fs::path& dir, const PlannedRun& run,
                                       const RunStream& stream, bool viewer) {
  const std::string& id = spec.points[run.point].id;
  std::error_code error;
  fs::create_directories(RunFolder(dir, id, run.seed).parent_path(), error);
  fs::create_directories(LogFile(dir, id, run.seed).parent_path(), error);
  fs::create_directories(StatusFile(dir, id, run.seed).parent_path(), error);
  fs::remove(StatusFile(dir, id, run.seed), error);
  const bool replay = stream.kind == RunStream::Kind::kReplay;
  std::vector<std::string> argv = {program, replay ? "replay" : "run"};
  if (replay) argv.push_back(stream.recording.string());
  argv.insert(argv.end(),
              {(dir / "points" / (id + ".yaml")).string(), "--seed", std::to_string(run.seed),
               "--out", RunFolder(dir, id, run.seed).string(), "--force", "--no-plots"});
  if (!viewer) argv.push_back("--no-viewer");
  if (stream.record_requested || stream.kind == RunStream::Kind::kRecord) {
    argv.push_back("--record");
  }
  return std::make_unique<ChildProcess>(argv, LogFile(dir, id, run.seed).string());
}

// How a run ended, recorded in status/<point>/seed_<S>.json (and returned).
json RecordRun(const StudySpec& spec, const fs::path& dir, const PlannedRun& run,
               const ChildStatus& status, bool timed_out, double elapsed, double peak_rss_mib,
               const std::string& stream) {
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
                 {"peak_rss_mib", peak_rss_mib},
                 {"stream", stream}};
  WriteFileAtomic(StatusFile(dir, id, run.seed), JsonFileText(record));
  return record;
}

}  // namespace study_internal

namespace {

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

}  // namespace

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
  RunQueue queue(spec, dir, todo, prepared.stream.shared, request.record);
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
  if (prepared.stream.shared) {
    std::printf(
        "study: the points differ only in their pipelines: each seed's stream is rendered once, "
        "recorded, and replayed for the other points (--no-replay renders every run)\n");
  } else if (request.replay && !prepared.stream.why.empty() && spec.points.size() > 1) {
    std::printf("study: every run renders (%s)\n", prepared.stream.why.c_str());
  }
  std::fflush(stdout);

  struct Active {
    PlannedRun run;
    RunStream stream;
    std::unique_ptr<ChildProcess> child;
    Clock::time_point start;
    bool timed_out = false;
  };
  std::vector<Active> active;
  std::size_t done = 0;
  int failed = 0;
  double run_seconds_sum = 0.0, peak_rss_mib = 0.0;
  json run_timing = json::array();
  const Clock::time_point loop_start = Clock::now();
  CatchStopSignals();
  while (!queue.empty() || !active.empty()) {
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
    while (static_cast<int>(active.size()) < jobs) {
      std::optional<std::pair<PlannedRun, RunStream>> t = queue.Next();
      if (!t) break;  // every run started, or the rest wait for a recording
      std::unique_ptr<ChildProcess> child =
          StartRun(program, spec, dir, t->first, t->second, request.viewer);
      active.push_back({t->first, std::move(t->second), std::move(child), Clock::now()});
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
      json record = RecordRun(spec, dir, it->run, *status, it->timed_out, elapsed,
                              it->child->peak_rss_mib(), StreamText(it->stream, dir));
      const bool finished = record["outcome"] == "finished";
      queue.Ended(it->run, finished);
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
          "study: [%zu/%zu] %s seed %llu %s%s in %.0f s; %zu running, %d failed, ETA %s; "
          "mean ATE (m):%s\n",
          done + already, planned_here, id.c_str(), static_cast<unsigned long long>(it->run.seed),
          finished ? "finished" : detail.c_str(),
          it->stream.kind == RunStream::Kind::kReplay   ? " (replayed)"
          : it->stream.kind == RunStream::Kind::kRecord ? " (recorded)"
                                                        : "",
          elapsed, active.size() - 1, failed,
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

}  // namespace corridorsim
