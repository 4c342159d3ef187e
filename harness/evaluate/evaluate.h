#pragma once
// `corridorsim evaluate RUN_DIR --estimate NAME=FILE ...`: any system's trajectory (TUM, or
// ov_eval with covariances) and landmark map scored offline against a run's exact truth, with the
// metric registry of metrics.json (docs/evaluation.md). Association by stamp within --max-dt, the
// truth interpolated at the estimate's stamp as the runner's metrics do; alignment none, SE(2),
// SE(3) or Sim(3); then the trajectory metrics (ATE, RPE, final error), NEES where the file has
// covariances, and map.<type> where a map is given.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/pose.h"
#include "harness/evaluate/alignment.h"
#include "harness/evaluate/evaluate_request.h"
#include "harness/evaluate/trajectory_file.h"
#include "harness/metrics/input.h"
#include "harness/metrics/trajectory.h"

namespace corridorsim::evaluate {

/// One estimate scored against the truth.
struct TrajectoryEvaluation {
  Similarity alignment;  // applied to every pose of the estimate
  Trajectory aligned;    // the estimate, every pose (and covariance) aligned
  // The poses with truth, aligned, planar (x, y, yaw), each with the truth at its stamp (and the
  // (x, y, yaw) covariance where NEES is scored): what MatchToTruth gives, built directly.
  metrics::MatchedTrajectory matched;
  nlohmann::ordered_json metrics;  // its object of evaluation.json (without file names)
};

/// Scores `estimate` against `truth` (the run's ground_truth.tum, planar): a pose is associated
/// when a truth stamp lies within max_dt_s of its own, and is compared with the truth interpolated
/// at its stamp (metrics::TruthAt); the alignment is fitted on the associated positions and
/// applied to `estimate` in place (it becomes `aligned`). NEES only with Alignment::kNone: after
/// an alignment the covariances no longer describe the error, and an ov_eval estimate's object
/// says so under "nees" instead. Throws InputError at `command line: --estimate` (naming `name`)
/// when the alignment cannot be fitted.
TrajectoryEvaluation EvaluateTrajectory(const std::vector<TruthPose>& truth, Trajectory estimate,
                                        Alignment alignment, double max_dt_s,
                                        const std::string& name);

/// <name>_aligned.tum and <name>_errors.csv of `evaluation` into the folder `out`, each written as
/// it is made (never held whole). Throws std::runtime_error naming a file that cannot be written.
void WriteEstimateFiles(const std::filesystem::path& out, const std::string& name,
                        Alignment alignment, const TrajectoryEvaluation& evaluation);

/// `estimate` (poses of world_from_camera, the camera's optical frame) as world_from_robot:
/// each pose times camera_from_robot; an ov_eval file's position covariance gains the lever
/// arm's share of its orientation covariance (both blocks taken in the world frame,
/// docs/evaluation.md), the orientation block is unchanged.
Trajectory ToRobotFrame(Trajectory estimate, const SE3& robot_from_camera);

/// `landmarks` moved by `alignment` (positions, covariances, points).
std::vector<slam::LandmarkEstimate> AlignLandmarks(std::vector<slam::LandmarkEstimate> landmarks,
                                                   const Similarity& alignment);

/// map.<type> of `landmarks` (already in the world frame) against `world`'s exact landmarks,
/// written into `object` through the registry (no frames: observed and missed are null).
void AddLandmarkMapMetrics(const worlds::World& world,
                           const std::vector<slam::LandmarkEstimate>& landmarks,
                           nlohmann::ordered_json& object);

/// The planar truth of a run's ground_truth.tum (x, y and the heading of its quaternion).
std::vector<TruthPose> TruthOfTrajectory(const Trajectory& truth);

/// The job: reads RUN_DIR's truth, then one estimate at a time (read, scored, its
/// <name>_aligned.tum and <name>_errors.csv written into the staging folder, let go), the maps,
/// writes evaluation.json (and plots/), prints the table and the expectations. Returns 0,
/// kExitExpectationsFailed (3) or kExitExtraFailed (4: the plots); bad input throws InputError
/// (exit 2) before the output folder is committed: nothing is written where it was asked. An
/// output that is, contains or lies inside an input is bad input (RefuseOutputOverInputs).
int RunEvaluate(const EvaluateRequest& request);

}  // namespace corridorsim::evaluate
