#pragma once
// `corridorsim study`: a scenario over many seeds (and sweep points), each run a `corridorsim run`
// child process of its own, J at a time; then the aggregate (harness/study/study_summary.h). A
// study folder is resumable: finished runs are kept and skipped, so a killed study loses at most
// the runs in flight. `--shard K/N` runs a deterministic part; `study merge` combines parts into
// the summary a whole study gives, byte for byte (docs/studies.md). Points that differ only in
// their pipelines share one sensor stream: each seed is rendered once, recorded, and replayed
// for the other points (`corridorsim replay`), with the same files. RunStudy is in study_run.cpp,
// MergeStudies in study_merge.cpp, WriteSlurmStudy in slurm.cpp; study_internal.h: what they
// share.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "harness/scenario/job.h"

namespace corridorsim {

inline constexpr int kMaxStudyJobs = 256;
inline constexpr int kMaxShards = 100000;

struct StudyRequest : JobRequest {
  std::optional<int> runs;  // --runs: seeds per point (overrides study.runs)
  int jobs = 0;             // --jobs: worker processes; 0 = the number of cores
  int shard_index = 0;      // --shard K/N: this part is K - 1 of N
  int shard_count = 1;
  bool plots = true;  // --no-plots skips plots/
  // --record: a recording.mcap in every run folder (`run --record`; replays record too).
  bool record = false;
  // --no-replay: every run renders, even when the points share one sensor stream (by default
  // each seed is recorded once and replayed for the other points: docs/studies.md, "Replay
  // instead of rendering").
  bool replay = true;
  bool viewer = true;  // --no-viewer skips report.html and the runs' viewer.html
  // --may-diverge: pipelines whose diverged runs do not fail the study (besides the study
  // file's study.may_diverge).
  std::vector<std::string> may_diverge;
  // `study merge DIR... --out OUT`: the parts to combine (instead of running a study).
  std::vector<std::filesystem::path> merge_dirs;
  // The program that runs each run (`corridorsim run`); empty: this executable.
  std::string run_program;
  // --slurm: write a Slurm job array (one task per shard) and a merge job that depends on it;
  // --submit: submit both with sbatch. slurm_tasks > 0 fixes the number of tasks, else it follows
  // the measured cost of a run and slurm_task_minutes.
  bool slurm = false;
  bool submit = false;
  int slurm_tasks = 0;
  double slurm_task_minutes = 60.0;
};

/// Slurm's default MaxArraySize allows array indices up to 1000: at most this many tasks.
inline constexpr int kMaxSlurmTasks = 1000;

/// Runs (or resumes) the study and writes the summary. Returns 0; 1 when a run failed or timed
/// out, or a pipeline not listed in may_diverge diverged (the study goes on and names them at
/// the end); 3 when a study expectation failed; 4 when
/// only plots/ or report.html failed. Throws InputError for bad input, before any run starts.
int RunStudy(const StudyRequest& request);

/// `study --slurm`: prepares the study folder, measures the cost of one run (the plan's first,
/// run here and kept as a result, in its shard's folder too, unless the folder has a finished run
/// with its cost), writes slurm/study.sbatch (a job array: task K runs `study --shard K/N` into
/// shards/K) and slurm/merge.sbatch (`study merge shards/* --out` the study folder), and with
/// --submit submits them (`sbatch --dependency=afterok:<array job>`). Returns 0, 1 when sbatch
/// fails.
int WriteSlurmStudy(const StudyRequest& request);

/// `study merge`: combines study folders of the same plan (shards, or partial resumes) into
/// request.out_dir and writes its summary. Same exit codes as RunStudy.
int MergeStudies(const StudyRequest& request);

}  // namespace corridorsim
