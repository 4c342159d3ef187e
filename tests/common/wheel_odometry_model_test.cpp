// Tests common/wheel_odometry_model.cpp: P1 eq. 13 on straight, turning-in-place and arc motion,
// its Jacobians F and G against central differences, and the order of P1 eq. 17's Q.

#include "common/wheel_odometry_model.h"

#include <cmath>
#include <numbers>

#include <catch2/catch.hpp>

#include "common/random.h"
#include "tests/support/jacobian_check.h"
#include "tests/support/tolerances.h"

namespace corridorsim {
namespace {

using test::kPoseTol;
constexpr double kPi = std::numbers::pi;
constexpr double kWheelbaseM = 0.33;  // a Pioneer 3-DX's track width

TEST_CASE("equal wheel distances drive straight along the heading", "[wheel_odometry]") {
  const SE2 start(1.0, -2.0, 0.7);
  const SE2 end = ApplyWheelOdometry(start, 0.25, 0.25, kWheelbaseM);
  CHECK(end.x() == Approx(1.0 + 0.25 * std::cos(0.7)).margin(kPoseTol));
  CHECK(end.y() == Approx(-2.0 + 0.25 * std::sin(0.7)).margin(kPoseTol));
  CHECK(end.yaw() == Approx(0.7).margin(kPoseTol));

  const SE2 back = ApplyWheelOdometry(start, -0.1, -0.1, kWheelbaseM);
  CHECK(back.x() == Approx(1.0 - 0.1 * std::cos(0.7)).margin(kPoseTol));
  CHECK(back.y() == Approx(-2.0 - 0.1 * std::sin(0.7)).margin(kPoseTol));
  CHECK(back.yaw() == Approx(0.7).margin(kPoseTol));
}

TEST_CASE("opposite wheel distances turn in place by (s_r - s_l) / B", "[wheel_odometry]") {
  const SE2 start(3.0, 4.0, -0.2);
  const double wheel_m = 0.05;
  const SE2 left_turn = ApplyWheelOdometry(start, -wheel_m, wheel_m, kWheelbaseM);
  CHECK(left_turn.x() == Approx(3.0).margin(kPoseTol));
  CHECK(left_turn.y() == Approx(4.0).margin(kPoseTol));
  CHECK(left_turn.yaw() == Approx(-0.2 + 2.0 * wheel_m / kWheelbaseM).margin(kPoseTol));

  // A half turn from yaw 3 wraps into (-pi, pi].
  const SE2 near_pi(0.0, 0.0, 3.0);
  const double half_turn_wheel_m = 0.5 * kPi * kWheelbaseM;
  const SE2 wrapped =
      ApplyWheelOdometry(near_pi, -half_turn_wheel_m, half_turn_wheel_m, kWheelbaseM);
  CHECK(wrapped.yaw() == Approx(3.0 - kPi).margin(kPoseTol));
  CHECK(wrapped.translation().norm() == Approx(0.0).margin(kPoseTol));
}

// Drives a quarter circle of radius 1 m (centre on the robot's left) in `steps` equal steps and
// returns the end pose; the exact end is (R sin 90 deg, R (1 - cos 90 deg)) = (1, 1) relative to
// the start, turned by 90 deg.
SE2 DriveQuarterCircle(const SE2& start, int steps) {
  const double radius_m = 1.0;
  const double turn_per_step_rad = 0.5 * kPi / steps;
  const double left_m = (radius_m - 0.5 * kWheelbaseM) * turn_per_step_rad;
  const double right_m = (radius_m + 0.5 * kWheelbaseM) * turn_per_step_rad;
  SE2 pose = start;
  for (int i = 0; i < steps; ++i) pose = ApplyWheelOdometry(pose, left_m, right_m, kWheelbaseM);
  return pose;
}

TEST_CASE("small steps along an arc follow the exact circle; the bias is the arc-to-chord ratio",
          "[wheel_odometry]") {
  // Start near yaw pi so that the heading wraps on the way.
  const SE2 start(2.0, -1.0, 2.9);
  const SE2 exact_end = start * SE2(1.0, 1.0, 0.5 * kPi);
  const double chord_m = std::sqrt(2.0);
  for (const int steps : {10, 100, 1000}) {
    INFO("steps " << steps);
    const SE2 end = DriveQuarterCircle(start, steps);
    // The heading is exact: each step turns by exactly its share.
    CHECK(NormalizeAngle(end.yaw() - exact_end.yaw()) == Approx(0.0).margin(kPoseTol));
    // Each step moves along the exact chord direction (the midpoint heading) but by the arc length
    // instead of the chord: the end lies on the line to the exact end, scaled by
    // (delta / 2) / sin(delta / 2) = 1 + delta^2 / 24 + O(delta^4).
    const double delta = 0.5 * kPi / steps;
    const double expected_overshoot_m = chord_m * (0.5 * delta / std::sin(0.5 * delta) - 1.0);
    const Eigen::Vector2d to_end = end.translation() - start.translation();
    const Eigen::Vector2d to_exact = exact_end.translation() - start.translation();
    CHECK(to_end.norm() - chord_m ==
          Approx(expected_overshoot_m).epsilon(test::kMotionModelBiasRel));
    CHECK(std::abs(to_end.normalized().dot(to_exact.normalized()) - 1.0) < kPoseTol);
  }
  // Fine steps: within a micrometre of the circle.
  const SE2 fine_end = DriveQuarterCircle(start, 1000);
  CHECK((fine_end.translation() - exact_end.translation()).norm() < 1e-6);
}

// (x, y, yaw) of a pose, with the yaw unwrapped next to `reference_yaw`, so that central
// differences across the wrap at pi stay small.
Eigen::Vector3d Unwrapped(const SE2& pose, double reference_yaw) {
  return {pose.x(), pose.y(), reference_yaw + NormalizeAngle(pose.yaw() - reference_yaw)};
}

TEST_CASE("F and G match central differences at random poses and wheel distances",
          "[wheel_odometry][jacobian]") {
  RandomStream rng(7, 0, "tests.wheel_odometry_model");
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d pose_params(rng.Uniform(-10, 10), rng.Uniform(-10, 10),
                                      rng.Uniform(-kPi, kPi));
    const Eigen::Vector2d lr(rng.Uniform(-0.5, 0.5), rng.Uniform(-0.5, 0.5));
    const double wheelbase_m = rng.Uniform(0.2, 0.6);
    const SE2 pose(pose_params.x(), pose_params.y(), pose_params.z());
    INFO("trial " << trial << ": pose " << pose_params.transpose() << ", (s_l, s_r) "
                  << lr.transpose() << ", B " << wheelbase_m);

    Eigen::Matrix3d d_pose_d_pose;
    Eigen::Matrix<double, 3, 2> d_pose_d_lr;
    const SE2 end =
        ApplyWheelOdometry(pose, lr.x(), lr.y(), wheelbase_m, &d_pose_d_pose, &d_pose_d_lr);
    const double reference_yaw = end.yaw();

    const Eigen::Matrix3d numerical_f = test::NumericalJacobian<3, 3>(
        [&](const Eigen::Vector3d& p) {
          return Unwrapped(
              ApplyWheelOdometry(SE2(p.x(), p.y(), p.z()), lr.x(), lr.y(), wheelbase_m),
              reference_yaw);
        },
        pose_params);
    test::CheckJacobian(d_pose_d_pose, numerical_f);

    const Eigen::Matrix<double, 3, 2> numerical_g = test::NumericalJacobian<3, 2>(
        [&](const Eigen::Vector2d& u) {
          return Unwrapped(ApplyWheelOdometry(pose, u.x(), u.y(), wheelbase_m), reference_yaw);
        },
        lr);
    test::CheckJacobian(d_pose_d_lr, numerical_g);

    // The Jacobian outputs do not change the pose.
    const SE2 plain = ApplyWheelOdometry(pose, lr.x(), lr.y(), wheelbase_m);
    CHECK(plain.x() == end.x());
    CHECK(plain.y() == end.y());
    CHECK(plain.yaw() == end.yaw());
  }
}

TEST_CASE("Q of P1 eq. 17 is diag(k |s_l|, k |s_r|) in the column order of G", "[wheel_odometry]") {
  const Eigen::Matrix2d q = WheelOdometryNoise(0.2, -0.05, 1e-3);
  CHECK(q(0, 0) == Approx(2e-4).margin(1e-18));
  CHECK(q(1, 1) == Approx(5e-5).margin(1e-18));
  CHECK(q(0, 1) == 0.0);
  CHECK(q(1, 0) == 0.0);
  CHECK(WheelOdometryNoise(0.3, 0.3, 0.0).isZero(0.0));
}

}  // namespace
}  // namespace corridorsim
