#pragma once
// Consistency metrics: NEES of the pose over (x, y, yaw) and NIS per landmark type, each against
// its two-sided 95 % chi-square bands (docs/metrics.md); and the error series CSV that plots the
// errors against their sigmas (P3 Fig. 18).

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "harness/metrics/input.h"
#include "harness/metrics/registry.h"
#include "harness/metrics/trajectory.h"

namespace corridorsim {

/// Per-time errors for plots: CSV "t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees",
/// one row per estimate with truth at its stamp; t in s; errors estimate minus truth (world frame,
/// yaw wrapped); sigmas from the covariance diagonal (a negative variance gives 0); NEES over 3
/// dof, empty where the covariance is not positive definite. A variance that is not finite gives
/// an empty sigma field, never `nan`: the readers take empty as missing. (MatchToTruth leaves
/// estimates that are not finite out.)
std::string ErrorSeriesCsv(const std::vector<TruthPose>& truth, const PipelineRecord& pipeline);
/// The same bytes for samples already matched to the truth (MatchToTruth's), handed to `sink` line
/// by line (the header first), never held whole: a long trajectory's file is written as it is
/// made (`corridorsim evaluate`).
void WriteErrorSeriesCsv(const metrics::MatchedTrajectory& matched,
                         const std::function<void(std::string_view)>& sink);

/// <pipeline>_nis.csv: one line per landmark update, in the pipeline's order: t (s), the landmark
/// type, the innovation's degrees of freedom, its NIS, and 1 when the update was applied (0: gated
/// out). Header `t,type,dof,nis,accepted`. Malformed innovations (the metrics count them) are
/// left out. Empty (no file) for a pipeline without landmark updates.
std::string NisSeriesCsv(const PipelineRecord& pipeline);

namespace metrics {

/// The smallest sigma (m for x and y, rad for yaw) a sample's covariance must have for its NEES
/// to count (0.1 mm, 0.1 mrad): smaller ones (the exactly known start and the first steps after
/// it) are skipped.
inline constexpr double kNeesMinSigma = 1e-4;

/// NEES e^T P^-1 e over 3 dof, or none when P is not finite or not positive definite.
std::optional<double> Nees(const Eigen::Vector3d& error, const Eigen::Matrix3d& covariance);

/// nees_* into the pipeline's object (nothing without samples).
void AddNeesMetrics(const MatchedTrajectory& matched, const MetricWriter& out);

/// nis.<type> for the types with innovations. Returns the malformed innovations (dof < 1, a NIS
/// that is negative or not finite): left out of the statistics, counted, never fatal.
std::size_t AddNisMetrics(const std::vector<slam::Innovation>& innovations,
                          const MetricWriter& out);

}  // namespace metrics
}  // namespace corridorsim
