#pragma once
// What the study's files share, internal to harness/study/: study_plan.cpp (the plan and the
// preparation of a study), study_folder.cpp (the folder's layout, its preparation and what it
// records), study_run.cpp (`study`: the runs J at a time), study_merge.cpp (`study merge`),
// study_finish.cpp (the summary, report and exit code of both) and slurm.cpp (`study --slurm`).

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/io/child_process.h"
#include "harness/study/study.h"
#include "harness/study/study_file.h"
#include "harness/study/study_summary.h"

namespace corridorsim::study_internal {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

/// The largest study.json read back (a plan of kMaxSweepPoints points is far below it).
inline constexpr std::uint64_t kMaxPlanBytes = std::uint64_t{64} << 20;

// study_folder.cpp: the study folder.

/// runs/<point>/seed_<S>, status/<point>/seed_<S>.json, logs/<point>/seed_<S>.log of `dir`.
fs::path RunFolder(const fs::path& dir, const std::string& point, std::uint64_t seed);
fs::path StatusFile(const fs::path& dir, const std::string& point, std::uint64_t seed);
fs::path LogFile(const fs::path& dir, const std::string& point, std::uint64_t seed);

/// Prepares the study folder `dir` for the plan `plan_text`: new (created with its marker), the
/// same study (resumed), or with `force` an earlier corridorsim output (removed first). Anything
/// else is bad input (InputError naming `option`).
void PrepareFolder(const fs::path& dir, const std::string& plan_text, bool force,
                   const std::string& option);

/// Every planned run's outcome as the folder records it: finished when its run folder has
/// metrics.json, failed or timed out when its status says so, else not run.
std::vector<StudyRunRecord> CollectRecords(const StudySpec& spec, const fs::path& dir);

// study_plan.cpp: the plan (study.json) and the preparation of a study.

/// What differs between two plans' plugin libraries ("" when nothing): the merge names it.
std::string PluginDifference(const json& a, const json& b);

/// The summary's view of a plan (for `merge`, which has the folders, not the study file);
/// InputError naming `file` when it is not a plan of this build or out of bounds.
StudySpec SpecFromPlan(const json& plan, const fs::path& file);

/// The plan in `file` (InputError when it is not JSON).
json ReadPlan(const fs::path& file);

/// One run of the plan: a point and a seed.
struct PlannedRun {
  std::size_t point;
  std::uint64_t seed;
};

/// The study loaded, its folder prepared (plan, points, shard) and the runs this shard still has
/// to run.
struct PreparedStudy {
  StudySpec spec;
  fs::path dir;
  std::vector<PlannedRun> todo;
  std::size_t planned_here = 0;
  std::size_t already = 0;
};

/// Loads the study, checks and prepares its folder (InputError before anything is written).
PreparedStudy PrepareStudy(const StudyRequest& request);

// study_run.cpp: the runs.

/// Seconds since `since`.
double Seconds(Clock::time_point since);

/// Starts one run: `<program> run <point scenario> --seed S --out runs/<point>/seed_S`.
std::unique_ptr<ChildProcess> StartRun(const std::string& program, const StudySpec& spec,
                                       const fs::path& dir, const PlannedRun& run, bool viewer);

/// How a run ended, recorded in status/<point>/seed_<S>.json (and returned).
json RecordRun(const StudySpec& spec, const fs::path& dir, const PlannedRun& run,
               const ChildStatus& status, bool timed_out, double elapsed, double peak_rss_mib);

// study_finish.cpp: the end of a study or a merge.

/// " --may-diverge a,b" as given, or "".
std::string MayDivergeArgument(const StudyRequest& request);

/// Writes the summary files, the report and the plots of the runs in `dir`, with `timing` (the
/// caller's part of timing.json); prints the closing table. Returns the exit code (RunStudy's).
int FinishStudy(const StudySpec& spec, const fs::path& dir, const StudyRequest& request,
                json timing);

}  // namespace corridorsim::study_internal
