// Tests slam/filter_support.cpp: bad sensor data is recognised before it reaches a filter, and
// the wheel-odometry prediction is P1 eqs. 13-17 on the robot block.
#include "slam/filter_support.h"

#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "common/wheel_odometry_model.h"
#include "tests/support/test_cameras.h"

namespace corridorsim::slam {
namespace {

CameraCalibration SmallCamera() {
  CameraCalibration c;
  c.id = "front";
  c.model = PinholeRadTan::FromFov(64, 48, 1.0);
  c.depth = DepthRange{0.5, 8.0};
  return c;
}

CameraInput Frame(TimeNs stamp, int width, int height, std::uint8_t level) {
  CameraInput input;
  input.image.stamp_ns = stamp;
  input.image.camera_id = "front";
  input.image.image = Image8(width, height, 3);
  std::fill(input.image.image.data.begin(), input.image.image.data.end(), level);
  return input;
}

TEST_CASE("odometry with a NaN, an absurd distance or an old stamp is refused", "[slam]") {
  WheelOdometry good;
  good.stamp_ns = 100;
  good.left_distance_m = 0.01;
  good.right_distance_m = 0.01;
  CHECK_FALSE(OdometryProblem(good, 50));
  WheelOdometry nan = good;
  nan.left_distance_m = std::numeric_limits<double>::quiet_NaN();
  CHECK(OdometryProblem(nan, 50));
  WheelOdometry inf = good;
  inf.right_distance_m = std::numeric_limits<double>::infinity();
  CHECK(OdometryProblem(inf, 50));
  WheelOdometry huge = good;
  huge.left_distance_m = 1e6;
  CHECK(OdometryProblem(huge, 50));
  CHECK(OdometryProblem(good, 200));  // out of time order
}

TEST_CASE("frames that are empty, of the wrong size or out of order are refused", "[slam]") {
  const CameraCalibration camera = SmallCamera();
  CHECK_FALSE(FrameProblem(Frame(10, 64, 48, 100), camera, -1));
  CHECK(FrameProblem(Frame(10, 0, 0, 100), camera, -1));
  CHECK(FrameProblem(Frame(10, 32, 48, 100), camera, -1));
  CHECK(FrameProblem(Frame(10, 64, 48, 100), camera, 10));  // same stamp again
  CHECK(FrameProblem(Frame(5, 64, 48, 100), camera, 10));   // older
  CameraInput with_depth = Frame(10, 64, 48, 100);
  with_depth.depth = StampedDepth{10, "front", ImageF(32, 24)};
  CHECK(FrameProblem(with_depth, camera, -1));
  with_depth.depth = StampedDepth{10, "front", ImageF(64, 48)};
  CHECK_FALSE(FrameProblem(with_depth, camera, -1));
}

TEST_CASE("a black frame and a depth image of zeros carry no evidence", "[slam]") {
  CHECK(IsBlackImage(Frame(1, 64, 48, 0).image.image));
  CHECK_FALSE(IsBlackImage(Frame(1, 64, 48, 90).image.image));
  ImageF zeros(64, 48, 0.0f);
  CHECK(HasNoValidDepth(zeros));
  zeros.at(3, 4) = std::numeric_limits<float>::quiet_NaN();
  CHECK(HasNoValidDepth(zeros));
  zeros.at(5, 6) = 1.5f;
  CHECK_FALSE(HasNoValidDepth(zeros));
}

TEST_CASE("the prediction is P1 eqs. 13-17 on the robot block and leaves landmarks alone",
          "[slam]") {
  ekf::EkfState state(Eigen::Vector3d(1, 2, 0.3), Eigen::Matrix3d::Identity() * 0.01);
  ekf::Augmentation a;
  a.value = Eigen::Vector2d(5, 5);
  a.d_value_d_measurement = Eigen::Matrix2d::Identity();
  a.measurement_noise = Eigen::Matrix2d::Identity() * 0.5;
  const ekf::BlockId landmark = state.Augment(a);
  WheelOdometry odometry;
  odometry.stamp_ns = 1;
  odometry.left_distance_m = 0.10;
  odometry.right_distance_m = 0.12;
  PredictWithWheelOdometry(odometry, 0.33, 1e-4, &state);

  Eigen::Matrix3d F;
  Eigen::Matrix<double, 3, 2> G;
  const SE2 expected = ApplyWheelOdometry(SE2(1, 2, 0.3), 0.10, 0.12, 0.33, &F, &G);
  CHECK(state.RobotPose().x() == Approx(expected.x()).epsilon(1e-12));
  CHECK(state.RobotPose().y() == Approx(expected.y()).epsilon(1e-12));
  CHECK(state.RobotPose().z() == Approx(expected.yaw()).epsilon(1e-12));
  const Eigen::Matrix3d P = F * (Eigen::Matrix3d::Identity() * 0.01) * F.transpose() +
                            G * WheelOdometryNoise(0.10, 0.12, 1e-4) * G.transpose();
  CHECK((state.Covariance(ekf::EkfState::robot(), ekf::EkfState::robot()) - P).norm() < 1e-12);
  CHECK((state.Covariance(landmark, landmark) - Eigen::Matrix2d::Identity() * 0.5).norm() == 0.0);
}

TEST_CASE("global nearest neighbour: the cheapest pairs first, each side once", "[slam]") {
  // Observation 0 gates onto landmarks 0 and 1; observation 1 onto landmark 0 only, closer. In
  // observation order, 0 would take landmark 0 and leave 1 with nothing.
  const std::vector<slam::GatedPair> pairs = {{0, 0, 4.0}, {0, 1, 6.0}, {1, 0, 0.5}};
  const std::vector<std::size_t> taken = slam::AssignClosestFirst(pairs);
  REQUIRE(taken.size() == 2);
  CHECK(taken[0] == 2);  // (1, 0) first: the cheapest
  CHECK(taken[1] == 1);  // then (0, 1): landmark 0 is taken
  // One landmark and two observations: only the closer one gets it.
  CHECK(slam::AssignClosestFirst({{0, 0, 2.0}, {1, 0, 1.0}}) == std::vector<std::size_t>{1});
  // Ties keep the order given; nothing in, nothing out.
  CHECK(slam::AssignClosestFirst({{0, 0, 1.0}, {1, 0, 1.0}}) == std::vector<std::size_t>{0});
  CHECK(slam::AssignClosestFirst({}).empty());
}

}  // namespace
}  // namespace corridorsim::slam
