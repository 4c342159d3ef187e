// `corridorsim study --slurm`: the study's runs as a Slurm array job and its merge as a job that
// depends on it (docs/studies.md, "Scale-out"). The plan and folder are prepared as for a local
// study (study_internal.h); the scripts quote every path they hold or refuse it.

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/child_process.h"
#include "common/io/stable_json.h"
#include "harness/run/run_folder.h"
#include "harness/study/study.h"
#include "harness/study/study_internal.h"

namespace corridorsim {

using namespace study_internal;

namespace {

// A path as one word of a POSIX shell: single-quoted, ' as '\''.
std::string ShellWord(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The study folder goes into the scripts' `#SBATCH --output=` lines. Slurm reads such a line
// with a syntax of its own (whitespace ends the value, quotes and '\' are its own, '#' starts a
// comment) and expands %-patterns in a file name; a newline would end the line, and what follows
// it would be a command of every task. None of that can be quoted there: such a folder is
// refused (exit 2) before anything is written.
void RequireSbatchPath(const fs::path& path, const std::string& option) {
  const std::string text = path.string();
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    const bool control = u < 0x20 || u == 0x7F;
    if (!control && std::string_view(" %\\\"'#").find(c) == std::string_view::npos) continue;
    std::string what = std::string("'") + c + "'";
    if (control) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "%02X", static_cast<unsigned>(u));
      what = std::string("a control character (\\x") + hex + ")";
    }
    throw InputError(SourceLocation{"command line", 0, 0}, option,
                     "'" + InputExcerpt(text) + "' holds " + what +
                         ", which the #SBATCH lines of a Slurm script cannot hold (no "
                         "whitespace, quotes, '\\', '#', '%' or control characters): choose "
                         "another folder");
  }
}

// The run measured for --slurm lies in the study folder; its shard (run k of the plan belongs
// to shard k mod N) gets a copy, so that the array task does not run it again. Best effort: a
// copy that fails leaves the shard to run it. The copy goes through a staging name, so a
// half-copied run never looks finished.
void KeepMeasuredRun(const StudyRequest& request, const StudySpec& spec, const fs::path& dir,
                     const PlannedRun& run, long tasks) {
  const std::string& id = spec.points[run.point].id;
  std::error_code error;
  if (!fs::is_regular_file(RunFolder(dir, id, run.seed) / "metrics.json", error)) return;
  const long index =
      static_cast<long>(run.point) * spec.runs + static_cast<long>(run.seed - spec.first_seed);
  StudyRequest part = request;
  part.shard_count = static_cast<int>(tasks);
  part.shard_index = static_cast<int>(index % tasks);
  part.out_dir = dir / "shards" / std::to_string(part.shard_index + 1);
  part.force = false;
  try {
    const fs::path shard = PrepareStudy(part).dir;
    const fs::path target = RunFolder(shard, id, run.seed);
    if (fs::exists(target / "metrics.json")) return;
    const fs::path staging = target.string() + ".partial-slurm";
    fs::remove_all(staging);
    fs::create_directories(target.parent_path());
    fs::copy(RunFolder(dir, id, run.seed), staging,
             fs::copy_options::recursive | fs::copy_options::copy_symlinks);
    for (const fs::path& file : {LogFile(dir, id, run.seed), StatusFile(dir, id, run.seed)}) {
      const fs::path to = shard / fs::relative(file, dir);
      fs::create_directories(to.parent_path());
      fs::copy_file(file, to, fs::copy_options::overwrite_existing);
    }
    fs::remove_all(target);
    fs::rename(staging, target);
  } catch (const std::exception& e) {
    std::printf("study --slurm: the measured run stays with its shard to run again (%s)\n",
                e.what());
  }
}

}  // namespace

int WriteSlurmStudy(const StudyRequest& request) {
  if (request.shard_count > 1) {
    throw InputError(SourceLocation{"command line", 0, 0}, "--slurm",
                     "writes the shards itself: not with --shard");
  }
  RequireSbatchPath(fs::absolute(request.out_dir), "--out");
  PreparedStudy prepared = PrepareStudy(request);
  const StudySpec& spec = prepared.spec;
  const fs::path dir = fs::absolute(prepared.dir);
  // The cost of one run: a finished run's record, else the plan's first run, run here.
  double run_seconds = 0.0, run_rss_mib = 0.0;
  PlannedRun measured{0, spec.first_seed};
  for (std::size_t point = 0; point < spec.points.size(); ++point) {
    for (int i = 0; i < spec.runs && run_seconds == 0.0; ++i) {
      measured = {point, spec.first_seed + static_cast<std::uint64_t>(i)};
      const fs::path status = StatusFile(dir, spec.points[point].id, measured.seed);
      std::error_code error;
      if (!fs::is_regular_file(status, error)) continue;
      try {
        const json s = json::parse(ReadRegularFile(status, kMaxPlanBytes));
        if (s.at("outcome") == "finished") {
          run_seconds = s.at("wall_seconds").get<double>();
          run_rss_mib = s.at("peak_rss_mib").get<double>();
        }
      } catch (const std::exception&) {
        // not a usable record: measured below
      }
    }
  }
  if (run_seconds == 0.0) {
    const PlannedRun first{0, spec.first_seed};
    measured = first;
    std::printf("study --slurm: measuring the cost of one run (%s seed %llu) here\n",
                spec.points[0].id.c_str(), static_cast<unsigned long long>(first.seed));
    std::fflush(stdout);
    const Clock::time_point start = Clock::now();
    CatchStopSignals();
    RunStream stream;
    stream.record_requested = request.record;
    std::unique_ptr<ChildProcess> child =
        StartRun(ThisProgram(), spec, dir, first, stream, request.viewer);
    std::optional<ChildStatus> status;
    bool timed_out = false;
    while (!(status = child->Poll())) {
      if (const int signal = StopSignal()) {
        child->Signal(signal);
        child->Wait();
        std::fprintf(stderr, "corridorsim: study --slurm stopped by signal %d (%s)\n", signal,
                     ::strsignal(signal));
        DieOfSignal(signal);
      }
      if (!timed_out && Seconds(start) > spec.run_timeout_s) {
        child->Kill();
        timed_out = true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    const json record = RecordRun(spec, dir, first, *status, timed_out, Seconds(start),
                                  child->peak_rss_mib(), StreamText(stream, dir));
    if (record["outcome"] != "finished") {
      std::printf("study --slurm: the measuring run %s (log: %s); nothing submitted\n",
                  record["detail"].get<std::string>().c_str(),
                  LogFile(dir, spec.points[0].id, first.seed).string().c_str());
      return 1;
    }
    run_seconds = record["wall_seconds"].get<double>();
    run_rss_mib = record["peak_rss_mib"].get<double>();
  }
  // Packing: about slurm_task_minutes of runs per task, at most kMaxSlurmTasks tasks.
  const long total = static_cast<long>(spec.points.size()) * spec.runs;
  long tasks = request.slurm_tasks > 0
                   ? request.slurm_tasks
                   : static_cast<long>(std::ceil(static_cast<double>(total) * run_seconds /
                                                 (60.0 * request.slurm_task_minutes)));
  tasks = std::clamp<long>(tasks, 1, std::min<long>(total, kMaxSlurmTasks));
  const long runs_per_task = (total + tasks - 1) / tasks;
  KeepMeasuredRun(request, spec, dir, measured, tasks);
  // Resources per task: one core; memory and time from the measured run with margins (a run's
  // cost varies with its world: 1.5x memory plus 256 MiB, 2x time plus 5 minutes).
  const long mem_mib = static_cast<long>(std::ceil(run_rss_mib * 1.5 + 256.0));
  const long minutes = static_cast<long>(
      std::ceil((static_cast<double>(runs_per_task) * run_seconds * 2.0 + 300.0) / 60.0));
  const std::string program = fs::read_symlink("/proc/self/exe").string();
  const std::string study_file = fs::absolute(request.scenario_file).string();
  std::string seed_args;
  if (request.runs) seed_args += " --runs " + std::to_string(*request.runs);
  if (request.seed) seed_args += " --seed " + std::to_string(*request.seed);
  seed_args += MayDivergeArgument(request);
  // Each task reuses renders within its shard (the runs of a seed that it holds); --no-replay
  // and --record go on to the tasks.
  if (request.record) seed_args += " --record";
  if (!request.replay) seed_args += " --no-replay";
  for (const std::string& setting : request.settings) seed_args += " --set " + ShellWord(setting);
  const fs::path slurm_dir = dir / "slurm";
  std::error_code error;
  fs::create_directories(slurm_dir, error);
  fs::create_directories(dir / "shards", error);
  const std::string array_script =
      "#!/bin/bash\n"
      "# corridorsim study as a Slurm job array (written by `corridorsim study --slurm`; "
      "docs/studies.md). Task K of N runs part K of the plan into shards/K.\n"
      "#SBATCH --job-name=corridorsim-study\n"
      "#SBATCH --array=1-" +
      std::to_string(tasks) +
      "\n"
      "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n"
      "#SBATCH --mem=" +
      std::to_string(mem_mib) +
      "M\n"
      "#SBATCH --time=" +
      std::to_string(minutes) +
      "\n"
      "#SBATCH --output=" +
      (slurm_dir / "task_%a.log").string() +
      "\n"
      "# Measured: one run " +
      FormatFixed(run_seconds, 1) + " s and " + FormatFixed(run_rss_mib, 0) + " MiB; " +
      std::to_string(runs_per_task) +
      " run(s) per task.\n"
      "set -euo pipefail\n"
      "exec " +
      ShellWord(program) + " study " + ShellWord(study_file) + seed_args +
      " --shard \"${SLURM_ARRAY_TASK_ID}/" + std::to_string(tasks) + "\" --jobs 1 --no-plots" +
      (request.viewer ? "" : " --no-viewer") + " --out " + ShellWord((dir / "shards").string()) +
      "/\"${SLURM_ARRAY_TASK_ID}\"\n";
  const std::string merge_script =
      "#!/bin/bash\n"
      "# Merges the job array's shards into the study folder (written by `corridorsim study "
      "--slurm`); submitted with --dependency=afterok on the array.\n"
      "#SBATCH --job-name=corridorsim-merge\n"
      "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=1\n#SBATCH --mem=1024M\n#SBATCH --time=60\n"
      "#SBATCH --output=" +
      (slurm_dir / "merge.log").string() +
      "\n"
      "set -euo pipefail\n"
      "shards=()\n"
      "for k in $(seq 1 " +
      std::to_string(tasks) + "); do shards+=(" + ShellWord((dir / "shards").string()) +
      "/\"$k\"); done\n"
      "exec " +
      ShellWord(program) + " study merge \"${shards[@]}\" --out " + ShellWord(dir.string()) +
      (request.plots ? "" : " --no-plots") + (request.viewer ? "" : " --no-viewer") + "\n";
  WriteFileAtomic(slurm_dir / "study.sbatch", array_script);
  WriteFileAtomic(slurm_dir / "merge.sbatch", merge_script);
  std::printf(
      "study --slurm: %ld run(s) in %ld task(s) of %ld run(s), each 1 core, %ld MiB, %ld "
      "min; wrote %s and %s\n",
      total, tasks, runs_per_task, mem_mib, minutes, (slurm_dir / "study.sbatch").string().c_str(),
      (slurm_dir / "merge.sbatch").string().c_str());
  if (!request.submit) {
    std::printf(
        "submit with: id=$(sbatch --parsable %s) && sbatch --dependency=afterok:${id%%%%;*} "
        "%s\n",
        ShellWord((slurm_dir / "study.sbatch").string()).c_str(),
        ShellWord((slurm_dir / "merge.sbatch").string()).c_str());
    return 0;
  }
  const auto sbatch = [&](const std::vector<std::string>& args,
                          const std::string& name) -> std::optional<std::string> {
    const fs::path log = slurm_dir / (name + ".sbatch.out");
    std::vector<std::string> argv = {"sbatch", "--parsable"};
    argv.insert(argv.end(), args.begin(), args.end());
    ChildProcess child(argv, log.string());
    const std::optional<ChildStatus> status = child.Wait();
    if (const int signal = StopSignal()) DieOfSignal(signal);
    std::string out;
    try {
      out = ReadRegularFile(log, 1 << 20);
    } catch (const std::exception&) {
    }
    std::string id;
    for (char c : out) {
      if (c < '0' || c > '9') break;
      id += c;
    }
    if (!status->succeeded() || id.empty()) {
      std::printf("study --slurm: sbatch %s (%s)\n", DescribeChildStatus(*status).c_str(),
                  out.c_str());
      return std::nullopt;
    }
    return id;
  };
  const std::optional<std::string> array_id =
      sbatch({(slurm_dir / "study.sbatch").string()}, "study");
  if (!array_id) return 1;
  const std::optional<std::string> merge_id =
      sbatch({"--dependency=afterok:" + *array_id, (slurm_dir / "merge.sbatch").string()}, "merge");
  if (!merge_id) return 1;
  WriteFileAtomic(
      slurm_dir / "jobs.json",
      JsonFileText(json{{"array_job", *array_id}, {"merge_job", *merge_id}, {"tasks", tasks}}));
  std::printf(
      "study --slurm: submitted array job %s and merge job %s; the summary appears in %s "
      "when the merge job ends (squeue -j %s,%s)\n",
      array_id->c_str(), merge_id->c_str(), dir.string().c_str(), array_id->c_str(),
      merge_id->c_str());
  return 0;
}

}  // namespace corridorsim
