#pragma once
// Trajectory metrics: estimates matched to the truth at their stamps, ATE unaligned and after the
// least-squares SE2 alignment, RPE over travelled distance, the final error (docs/metrics.md).

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "harness/metrics/input.h"
#include "harness/metrics/registry.h"

namespace corridorsim::metrics {

struct MatchedSample {
  TimeNs stamp_ns = 0;
  SE2 estimate;
  SE2 truth;
  Eigen::Matrix3d covariance;
};

struct MatchedTrajectory {
  std::vector<MatchedSample> samples;
  std::size_t without_truth = 0;           // estimates outside the truth's time span
  std::size_t non_finite_estimates = 0;    // malformed: a pose that is not finite (left out)
  std::size_t non_finite_covariances = 0;  // malformed: a covariance with NaN or inf (kept)
};

/// The truth at `stamp`: exact on the grid, interpolated between grid points, none outside.
std::optional<SE2> TruthAt(const std::vector<TruthPose>& truth, TimeNs stamp);

/// Every estimate with a finite pose and truth at its stamp. Truth out of stamp order is a bug of
/// the runner (aborts); malformed estimates are counted, never fatal.
MatchedTrajectory MatchToTruth(const std::vector<TruthPose>& truth,
                               const std::vector<EstimateSample>& estimates);

/// The planar pose a reader of the run's TUM files gets back from the line sim::TumLine writes
/// for `pose`: x and y parsed from their six decimals, yaw = 2 atan2(qz, qw) of the printed
/// quaternion (nine decimals). The runner scores these (PosesAsWritten), so that metrics.json's
/// trajectory numbers are a function of ground_truth.tum and <pipeline>.tum alone: any reader
/// that repeats the arithmetic (corridorsim.Run.ate, docs/analysis.md) gets them to the last
/// digit. A NaN coordinate stays NaN (the line says "nan").
SE2 PoseAsWritten(const SE2& pose);
std::vector<TruthPose> PosesAsWritten(const std::vector<TruthPose>& poses);
std::vector<EstimateSample> PosesAsWritten(const std::vector<EstimateSample>& estimates);

/// Estimate minus truth in the world frame: (x m, y m, yaw rad wrapped to (-pi, pi]).
Eigen::Vector3d PoseError(const SE2& estimate, const SE2& truth);

/// Closed-form least-squares rotation + translation in the plane (Horn / Umeyama without scale)
/// that maps the estimated positions onto the true ones: truth ~ aligned_from_estimate * estimate.
SE2 AlignPositions(const std::vector<MatchedSample>& samples);

/// samples ... final_yaw_error_rad into the pipeline's object (nothing past the counts without
/// samples).
void AddTrajectoryMetrics(const MatchedTrajectory& matched, const MetricWriter& out);

}  // namespace corridorsim::metrics
