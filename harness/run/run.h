#pragma once
// `corridorsim run`: one scenario closed loop. Every pipeline of the scenario runs on the same
// sensor stream (so their comparison is paired), is scored against the ground truth, and the
// run folder gets trajectories, metrics, events, maps, plots and optionally a dataset export.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "harness/scenario/job.h"

namespace corridorsim {

struct RunRequest : JobRequest {
  std::optional<std::filesystem::path> export_dir;  // --export: a dataset for other systems
  bool plots = true;                                // --no-plots skips plots/
  bool viewer = true;                               // --no-viewer skips viewer.html
  // --keep-frames: downscaled JPEGs of the rendered frames in frames/ (within the budget below),
  // which viewer.html shows with the detections drawn on them (docs/viewer.md).
  bool keep_frames = false;
  double keep_frames_budget_mb = 20.0;  // --keep-frames-mb, 1 to 40
  bool check_only = false;  // --check: load, build the world, path, pipelines and rig; run nothing
  // --record: the run's stream, truth, estimates and world as recording.mcap in the run folder
  // (MCAP with ROS 2 messages, docs/recordings.md); --record-topics keeps only the topics that
  // match its patterns; --record-compression zstd (default), lz4 or none.
  bool record = false;
  // --record-bag: the same topics as recording.bag, a ROS 1 bag (with or without --record).
  bool record_bag = false;
  std::string record_topics;
  std::string record_compression = "zstd";
  // `corridorsim replay`: this recording's stream replaces the simulation and the rendering; the
  // scenario (scenario_file, or the recording's own when empty) must match the recording's world,
  // robot, path and sensors (its pipelines may differ).
  std::optional<std::filesystem::path> replay;
};

/// Exit code of a run whose expectations did not all pass (0 success, 1 failure, 2 bad input).
inline constexpr int kExitExpectationsFailed = 3;
/// Exit code of a run whose results are written and committed but an extra (maps/, plots/,
/// viewer.html, the --export dataset) failed. kExitExpectationsFailed takes precedence.
inline constexpr int kExitExtraFailed = 4;
/// Exit code of a run in which a pipeline failed (a call into it threw: a plugin's bug, docs/
/// plugins.md): the other pipelines' results are written and committed, the failed one's metrics
/// are `health.failed` and events.json says why. Takes precedence over 3 and 4.
inline constexpr int kExitPipelineFailed = 5;

/// Whether a run that exited with `exit_code` left its results written and committed: 0, 3, 4 and
/// 5 do (studies and suites read them), anything else does not.
inline bool RunWroteResults(int exit_code) {
  return exit_code == 0 || exit_code == kExitExpectationsFailed || exit_code == kExitExtraFailed ||
         exit_code == kExitPipelineFailed;
}

/// Runs the scenario; prints progress and a closing table. Returns 0, kExitPipelineFailed when a
/// pipeline failed, else kExitExpectationsFailed when an expectation failed, or kExitExtraFailed
/// when an extra failed (and every expectation passed). Throws InputError for bad input (before
/// anything runs).
int RunScenario(const RunRequest& request);

}  // namespace corridorsim
