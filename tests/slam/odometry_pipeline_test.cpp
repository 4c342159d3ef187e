// Tests slam/odometry_pipeline.cpp: dead reckoning follows P1 eq. 13 and its covariance follows
// P1 eqs. 14-17.
#include "slam/odometry_pipeline.h"

#include <cmath>
#include <numbers>

#include <catch2/catch.hpp>

#include "common/random.h"
#include "common/wheel_odometry_model.h"
#include "tests/support/odometry_message.h"
#include "tests/support/pioneer_calibration.h"

namespace corridorsim::slam {
namespace {

using test::OdometryMessage;
using test::PioneerCalibration;

TEST_CASE("the odometry pipeline starts at the given pose with zero covariance", "[slam]") {
  OdometryPipeline pipeline(OdometryPipelineOptions{}, PioneerCalibration());
  pipeline.Initialize(5, SE2(1.0, 2.0, 0.5));
  const PoseEstimate e = pipeline.Estimate();
  CHECK(e.stamp_ns == 5);
  CHECK(e.world_from_robot.x() == 1.0);
  CHECK(e.world_from_robot.yaw() == 0.5);
  CHECK(e.covariance.isZero());
  CHECK(pipeline.cameras_used().empty());
}

TEST_CASE("straight driving grows the along-track variance by k s / 2 and bends nothing",
          "[slam]") {
  OdometryPipelineOptions options;
  options.k_m = 2e-4;
  OdometryPipeline pipeline(options, PioneerCalibration());
  pipeline.Initialize(0, SE2(0, 0, 0));
  const int n = 100;
  const double step = 0.01;  // 1 m in all
  for (int i = 1; i <= n; ++i) pipeline.OnOdometry(OdometryMessage(i, step, step));
  const PoseEstimate e = pipeline.Estimate();
  CHECK(e.world_from_robot.x() == Approx(1.0).epsilon(1e-12));
  CHECK(e.world_from_robot.y() == Approx(0.0).margin(1e-15));
  // Along track: x = sum (s_l + s_r) / 2, each wheel variance k s: var x = n * 2 k s / 4.
  CHECK(e.covariance(0, 0) == Approx(n * 2 * options.k_m * step / 4).epsilon(1e-9));
  // Heading: var yaw = n * 2 k s / B^2.
  const double b = PioneerCalibration().wheelbase_m;
  CHECK(e.covariance(2, 2) == Approx(n * 2 * options.k_m * step / (b * b)).epsilon(1e-9));
  // Cross track grows through the heading (F couples y and yaw): positive, correlated with yaw.
  CHECK(e.covariance(1, 1) > 0);
  CHECK(e.covariance(1, 2) > 0);
  CHECK(e.covariance.isApprox(e.covariance.transpose()));
  CHECK(e.stamp_ns == n);
}

TEST_CASE("the propagated covariance matches the spread of simulated wheel noise", "[slam]") {
  // Monte Carlo: wheel distances with variance k|s| per message, P1 eq. 17; an arc of 2 m.
  OdometryPipelineOptions options;
  options.k_m = 1e-4;
  const int messages = 200, runs = 3000;
  const double left = 0.0095, right = 0.0105;
  OdometryPipeline reference(options, PioneerCalibration());
  reference.Initialize(0, SE2());
  for (int i = 1; i <= messages; ++i) reference.OnOdometry(OdometryMessage(i, left, right));
  const PoseEstimate expected = reference.Estimate();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  RandomStream rng(11, 0, "tests.slam.odometry");
  for (int r = 0; r < runs; ++r) {
    SE2 pose;
    for (int i = 1; i <= messages; ++i) {
      const double l = left + rng.Normal(0, std::sqrt(options.k_m * left));
      const double rr = right + rng.Normal(0, std::sqrt(options.k_m * right));
      pose = ApplyWheelOdometry(pose, l, rr, PioneerCalibration().wheelbase_m);
    }
    Eigen::Vector3d d(pose.x() - expected.world_from_robot.x(),
                      pose.y() - expected.world_from_robot.y(),
                      NormalizeAngle(pose.yaw() - expected.world_from_robot.yaw()));
    scatter += d * d.transpose();
  }
  scatter /= runs;
  // Linearised propagation against the sample covariance: within 10 % on the diagonal (the
  // sampling error of a variance over 3000 runs is about 2.6 %).
  for (int i = 0; i < 3; ++i) {
    CHECK(scatter(i, i) == Approx(expected.covariance(i, i)).epsilon(0.1));
  }
}

TEST_CASE("odometry pipeline options reject a negative k", "[slam]") {
  OdometryPipelineOptions options;
  CHECK_FALSE(options.Check());
  options.k_m = -1;
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "k_m");
}

TEST_CASE("odometry with a NaN or out of time order is refused and counted, not applied",
          "[slam]") {
  OdometryPipeline pipeline(OdometryPipelineOptions{}, test::PioneerCalibration());
  pipeline.Initialize(0, SE2(0.0, 0.0, 0.0));
  pipeline.OnOdometry(OdometryMessage(10, 0.1, 0.1));
  const PoseEstimate before = pipeline.Estimate();
  pipeline.OnOdometry(OdometryMessage(20, std::nan(""), 0.1));
  pipeline.OnOdometry(OdometryMessage(5, 0.1, 0.1));  // older than the last one
  const PoseEstimate after = pipeline.Estimate();
  CHECK(after.world_from_robot.x() == before.world_from_robot.x());
  CHECK(after.covariance == before.covariance);
  CHECK(after.covariance.allFinite());
  CHECK(pipeline.health().rejected_odometry == 2);
  pipeline.OnOdometry(OdometryMessage(30, 0.1, 0.1));  // good data afterwards is used
  CHECK(pipeline.Estimate().world_from_robot.x() > before.world_from_robot.x());
}

}  // namespace
}  // namespace corridorsim::slam
