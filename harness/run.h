#pragma once
// `corridorsim run`: one scenario closed loop. Every pipeline of the scenario runs on the same
// sensor stream (so their comparison is paired), is scored against the ground truth, and the
// run folder gets trajectories, metrics, events, maps, plots and optionally a dataset export.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "harness/job.h"

namespace corridorsim {

struct RunRequest : JobRequest {
  std::optional<std::filesystem::path> export_dir;  // --export: a dataset for other systems
  bool plots = true;                                // --no-plots skips plots/
  bool check_only = false;  // --check: load, build the world, path, pipelines and rig; run nothing
};

/// Exit code of a run whose expectations did not all pass (0 success, 1 failure, 2 bad input).
inline constexpr int kExitExpectationsFailed = 3;

/// Runs the scenario; prints progress and a closing table. Returns 0, or kExitExpectationsFailed
/// when an expectation failed. Throws InputError for bad input (before anything runs).
int RunScenario(const RunRequest& request);

}  // namespace corridorsim
