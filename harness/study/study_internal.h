#pragma once
// What the study's files share (study.cpp: run, resume and merge; slurm.cpp: the Slurm scripts):
// where a run's folder, status and log lie, the plan's size bound, and the preparation, start and
// record of a run. Internal to harness/study/.

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

namespace corridorsim::study_internal {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

/// The largest study.json read back (a plan of kMaxSweepPoints points is far below it).
inline constexpr std::uint64_t kMaxPlanBytes = std::uint64_t{64} << 20;

/// Seconds since `since`.
double Seconds(Clock::time_point since);

/// runs/<point>/seed_<S>, status/<point>/seed_<S>.json, logs/<point>/seed_<S>.log of `dir`.
fs::path RunFolder(const fs::path& dir, const std::string& point, std::uint64_t seed);
fs::path StatusFile(const fs::path& dir, const std::string& point, std::uint64_t seed);
fs::path LogFile(const fs::path& dir, const std::string& point, std::uint64_t seed);

/// " --may-diverge a,b" as given, or "".
std::string MayDivergeArgument(const StudyRequest& request);

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

/// Starts one run: `<program> run <point scenario> --seed S --out runs/<point>/seed_S`.
std::unique_ptr<ChildProcess> StartRun(const std::string& program, const StudySpec& spec,
                                       const fs::path& dir, const PlannedRun& run, bool viewer);

/// How a run ended, recorded in status/<point>/seed_<S>.json (and returned).
json RecordRun(const StudySpec& spec, const fs::path& dir, const PlannedRun& run,
               const ChildStatus& status, bool timed_out, double elapsed, double peak_rss_mib);

}  // namespace corridorsim::study_internal
