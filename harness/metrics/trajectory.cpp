#include "harness/metrics/trajectory.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <string>

#include "common/error.h"
#include "harness/metrics/stats.h"
#include "sim/simulation.h"

namespace corridorsim::metrics {

using Eigen::Vector2d;
using Eigen::Vector3d;

std::optional<SE2> TruthAt(const std::vector<TruthPose>& truth, TimeNs stamp) {
  const auto it = std::lower_bound(truth.begin(), truth.end(), stamp,
                                   [](const TruthPose& p, TimeNs s) { return p.stamp_ns < s; });
  if (it == truth.end()) return std::nullopt;
  if (it->stamp_ns == stamp) return it->world_from_robot;
  if (it == truth.begin()) return std::nullopt;
  const TruthPose& before = *(it - 1);
  const double t = static_cast<double>(stamp - before.stamp_ns) /
                   static_cast<double>(it->stamp_ns - before.stamp_ns);
  return SE2::Interpolate(before.world_from_robot, it->world_from_robot, t);
}

MatchedTrajectory MatchToTruth(const std::vector<TruthPose>& truth,
                               const std::vector<EstimateSample>& estimates) {
  CheckOrDie(std::is_sorted(
                 truth.begin(), truth.end(),
                 [](const TruthPose& a, const TruthPose& b) { return a.stamp_ns < b.stamp_ns; }),
             "ComputeMetrics", "truth is not in stamp order");
  MatchedTrajectory out;
  for (const EstimateSample& e : estimates) {
    const SE2& pose = e.world_from_robot;
    if (!std::isfinite(pose.x()) || !std::isfinite(pose.y()) || !std::isfinite(pose.yaw())) {
      ++out.non_finite_estimates;
      continue;
    }
    if (!e.covariance.allFinite()) ++out.non_finite_covariances;
    const std::optional<SE2> t = TruthAt(truth, e.stamp_ns);
    if (!t) {
      ++out.without_truth;
      continue;
    }
    out.samples.push_back({e.stamp_ns, e.world_from_robot, *t, e.covariance});
  }
  return out;
}

SE2 PoseAsWritten(const SE2& pose) {
  // The very line the run folder holds (the stamp does not change the pose's digits).
  const std::string line = sim::TumLine(0, SE3::FromSE2(pose));
  std::array<double, 8> fields{};
  const char* cursor = line.c_str();
  for (double& field : fields) {
    char* end = nullptr;
    field = std::strtod(cursor, &end);
    CheckOrDie(end != cursor, "metrics::PoseAsWritten", "sim::TumLine wrote fewer than 8 fields");
    cursor = end;
  }
  // t x y z qx qy qz qw: a planar pose's quaternion is (0, 0, sin(yaw/2), cos(yaw/2)).
  return SE2(fields[1], fields[2], 2.0 * std::atan2(fields[6], fields[7]));
}

std::vector<TruthPose> PosesAsWritten(const std::vector<TruthPose>& poses) {
  std::vector<TruthPose> out = poses;
  for (TruthPose& p : out) p.world_from_robot = PoseAsWritten(p.world_from_robot);
  return out;
}

std::vector<EstimateSample> PosesAsWritten(const std::vector<EstimateSample>& estimates) {
  std::vector<EstimateSample> out = estimates;
  for (EstimateSample& e : out) e.world_from_robot = PoseAsWritten(e.world_from_robot);
  return out;
}

Vector3d PoseError(const SE2& estimate, const SE2& truth) {
  return {estimate.x() - truth.x(), estimate.y() - truth.y(),
          NormalizeAngle(estimate.yaw() - truth.yaw())};
}

SE2 AlignPositions(const std::vector<MatchedSample>& samples) {
  Vector2d mean_estimate = Vector2d::Zero();
  Vector2d mean_truth = Vector2d::Zero();
  for (const MatchedSample& s : samples) {
    mean_estimate += s.estimate.translation();
    mean_truth += s.truth.translation();
  }
  const double n = static_cast<double>(samples.size());
  mean_estimate /= n;
  mean_truth /= n;
  double sum_dot = 0.0;
  double sum_cross = 0.0;
  for (const MatchedSample& s : samples) {
    const Vector2d a = s.estimate.translation() - mean_estimate;
    const Vector2d b = s.truth.translation() - mean_truth;
    sum_dot += a.dot(b);
    sum_cross += a.x() * b.y() - a.y() * b.x();
  }
  // All estimated positions equal: any rotation fits; keep none.
  const double yaw = (sum_dot == 0.0 && sum_cross == 0.0) ? 0.0 : std::atan2(sum_cross, sum_dot);
  const SE2 rotation(0.0, 0.0, yaw);
  return SE2(mean_truth - rotation * mean_estimate, yaw);
}

void AddTrajectoryMetrics(const MatchedTrajectory& matched, const MetricWriter& out) {
  const std::vector<MatchedSample>& samples = matched.samples;
  out.Count("samples", samples.size());
  out.Count("samples_without_truth", matched.without_truth);
  if (samples.empty()) return;

  // Distance travelled along the truth, cumulative per sample (RPE pairs are chosen by it).
  std::vector<double> travelled_m(samples.size(), 0.0);
  for (std::size_t i = 1; i < samples.size(); ++i) {
    travelled_m[i] = travelled_m[i - 1] +
                     (samples[i].truth.translation() - samples[i - 1].truth.translation()).norm();
  }
  out.Set("distance_travelled_m", travelled_m.back());

  // ATE, unaligned: the filters share the start pose, so the world frames agree.
  Stats ate;
  Stats ate_yaw;
  for (const MatchedSample& s : samples) {
    const Vector3d e = PoseError(s.estimate, s.truth);
    ate.Add(e.head<2>().norm());
    ate_yaw.Add(std::abs(e.z()));
  }
  out.Set("ate_rmse_m", ate.rms());
  out.Set("ate_mean_m", ate.mean());
  out.Set("ate_max_m", ate.maximum());
  out.Set("ate_yaw_rmse_rad", ate_yaw.rms());

  // ATE after the least-squares SE2 alignment of the positions.
  const SE2 aligned_from_estimate = AlignPositions(samples);
  Stats aligned;
  for (const MatchedSample& s : samples) {
    aligned.Add((aligned_from_estimate * s.estimate.translation() - s.truth.translation()).norm());
  }
  out.Set("ate_aligned_rmse_m", aligned.rms());
  out.Set("ate_aligned_mean_m", aligned.mean());
  out.Set("ate_aligned_max_m", aligned.maximum());
  out.Set("alignment.x_m", aligned_from_estimate.x());
  out.Set("alignment.y_m", aligned_from_estimate.y());
  out.Set("alignment.yaw_rad", aligned_from_estimate.yaw());

  // RPE: for each sample i the first j whose truth distance from i reaches d; the error of the
  // relative motion is (truth_i^-1 truth_j)^-1 (estimate_i^-1 estimate_j).
  for (const int distance_m : kRpeDistancesM) {
    Stats trans;
    Stats yaw;
    std::size_t j = 0;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      j = std::max(j, i + 1);
      while (j < samples.size() && travelled_m[j] - travelled_m[i] < distance_m) ++j;
      if (j >= samples.size()) break;
      const SE2 truth_motion = samples[i].truth.Inverse() * samples[j].truth;
      const SE2 estimate_motion = samples[i].estimate.Inverse() * samples[j].estimate;
      const SE2 error = truth_motion.Inverse() * estimate_motion;
      trans.Add(error.translation().norm());
      yaw.Add(std::abs(error.yaw()));
    }
    const std::string prefix = "rpe_" + std::to_string(distance_m) + "m_";
    out.Set(prefix + "trans_rmse_m", trans.rms());
    out.Set(prefix + "yaw_rmse_rad", yaw.rms());
    out.Count(prefix + "pairs", trans.count);
  }

  const Vector3d final_error = PoseError(samples.back().estimate, samples.back().truth);
  out.Set("final_position_error_m", final_error.head<2>().norm());
  out.Set("final_yaw_error_rad", std::abs(final_error.z()));
}

}  // namespace corridorsim::metrics
