#include "slam/odometry_pipeline.h"

#include <cmath>

#include "common/wheel_odometry_model.h"

namespace corridorsim::slam {

std::optional<OptionsProblem> OdometryPipelineOptions::Check() const {
  return CheckOptionBounds(OdometryPipelineOptionsTable(), *this);
}

OdometryPipeline::OdometryPipeline(const OdometryPipelineOptions& options,
                                   const Calibration& calibration, std::uint64_t /*seed*/)
    : options_(options), wheelbase_m_(calibration.wheelbase_m) {
  // The harness builds the calibration from checked options: an invalid one is a bug.
  CheckOrDie(!calibration.Check(), "slam::OdometryPipeline", "the calibration fails its Check()");
}

void OdometryPipeline::Initialize(TimeNs stamp_ns, const SE2& world_from_robot) {
  estimate_.stamp_ns = stamp_ns;
  estimate_.world_from_robot = world_from_robot;
  estimate_.covariance.setZero();  // the start pose is known exactly
}

void OdometryPipeline::OnOdometry(const WheelOdometry& odometry) {
  // Bad data never reaches the estimate: a non-finite distance or a message out of time order
  // is counted and dropped.
  if (!std::isfinite(odometry.left_distance_m) || !std::isfinite(odometry.right_distance_m) ||
      odometry.stamp_ns < estimate_.stamp_ns) {
    ++health_.rejected_odometry;
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  Eigen::Matrix3d F;
  Eigen::Matrix<double, 3, 2> G;
  // P1 eq. 13: the motion model; eq. 14: P = F P F^T + G Q G^T with Q of eq. 17.
  estimate_.world_from_robot =
      ApplyWheelOdometry(estimate_.world_from_robot, odometry.left_distance_m,
                         odometry.right_distance_m, wheelbase_m_, &F, &G);
  const Eigen::Matrix2d Q =
      WheelOdometryNoise(odometry.left_distance_m, odometry.right_distance_m, options_.k_m);
  estimate_.covariance = F * estimate_.covariance * F.transpose() + G * Q * G.transpose();
  estimate_.covariance = 0.5 * (estimate_.covariance + estimate_.covariance.transpose());
  estimate_.stamp_ns = odometry.stamp_ns;
  predict_time_ += std::chrono::steady_clock::now() - t0;
}

std::map<std::string, double> OdometryPipeline::stage_seconds() const {
  return {{"predict", std::chrono::duration<double>(predict_time_).count()}};
}

}  // namespace corridorsim::slam
