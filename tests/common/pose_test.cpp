#include "common/pose.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/tolerances.h"

namespace corridorsim {
namespace {

using test::kPoseTol;
constexpr double kPi = std::numbers::pi;

template <class A, class B>
double MaxAbsDiff(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  return (a - b).cwiseAbs().maxCoeff();
}

std::vector<SE2> SamplePoses2d() {
  return {SE2(), SE2(1.0, -2.0, 0.3), SE2(-4.5, 0.25, 3.1), SE2(0.1, 7.0, -2.9),
          SE2(2.0, 2.0, kPi)};
}

std::vector<SE3> SamplePoses3d() {
  return {SE3(), SE3::FromYawPitchRoll(0.3, -0.2, 0.1, Eigen::Vector3d(1.0, 2.0, 3.0)),
          SE3::FromYawPitchRoll(-2.8, 1.2, 2.5, Eigen::Vector3d(-0.5, 4.0, -1.0)),
          SE3::FromSE2(SE2(3.0, -1.0, 2.0), 1.5)};
}

TEST_CASE("NormalizeAngle wraps into the half-open interval from -pi to +pi, keeping +pi",
          "[pose]") {
  CHECK(NormalizeAngle(0.0) == 0.0);
  CHECK(NormalizeAngle(kPi) == kPi);
  CHECK(NormalizeAngle(-kPi) == kPi);
  CHECK(NormalizeAngle(3.0 * kPi) == Approx(kPi).margin(kPoseTol));
  CHECK(NormalizeAngle(2.0 * kPi + 0.1) == Approx(0.1).margin(kPoseTol));
  CHECK(NormalizeAngle(-0.1 - 4.0 * kPi) == Approx(-0.1).margin(kPoseTol));
  for (double angle = -20.0; angle <= 20.0; angle += 0.37) {
    INFO("angle " << angle);
    const double wrapped = NormalizeAngle(angle);
    CHECK(wrapped > -kPi);
    CHECK(wrapped <= kPi);
    CHECK(std::cos(wrapped) == Approx(std::cos(angle)).margin(kPoseTol));
    CHECK(std::sin(wrapped) == Approx(std::sin(angle)).margin(kPoseTol));
  }
}

TEST_CASE("SE2 stores yaw normalised and composes yaw with wrapping", "[pose]") {
  CHECK(SE2(0.0, 0.0, 2.0 * kPi + 0.5).yaw() == Approx(0.5).margin(kPoseTol));
  const SE2 turned = SE2(0.0, 0.0, 3.0) * SE2(0.0, 0.0, 3.0);
  CHECK(turned.yaw() == Approx(6.0 - 2.0 * kPi).margin(kPoseTol));
}

TEST_CASE("SE2 maps a robot-frame point into the world frame", "[pose]") {
  const SE2 world_from_robot(1.0, 2.0, kPi / 2.0);
  const Eigen::Vector2d p_in_world = world_from_robot * Eigen::Vector2d(1.0, 0.0);
  CHECK(MaxAbsDiff(p_in_world, Eigen::Vector2d(1.0, 3.0)) <= kPoseTol);
}

TEST_CASE("SE2 composition, point transform and matrix form agree", "[pose]") {
  const Eigen::Vector2d p(0.7, -1.3);
  for (const SE2& a : SamplePoses2d()) {
    for (const SE2& b : SamplePoses2d()) {
      INFO("a = " << a.Log().transpose() << ", b = " << b.Log().transpose());
      CHECK(MaxAbsDiff((a * b).ToMatrix(), a.ToMatrix() * b.ToMatrix()) <= kPoseTol);
      CHECK(MaxAbsDiff((a * b) * p, a * (b * p)) <= kPoseTol);
      CHECK(MaxAbsDiff(a * p, (a.ToMatrix() * p.homogeneous()).head<2>()) <= kPoseTol);
    }
  }
}

TEST_CASE("SE2 times its inverse is the identity", "[pose]") {
  for (const SE2& pose : SamplePoses2d()) {
    INFO("pose = " << pose.Log().transpose());
    CHECK(MaxAbsDiff((pose * pose.Inverse()).ToMatrix(), Eigen::Matrix3d::Identity()) <= kPoseTol);
    CHECK(MaxAbsDiff((pose.Inverse() * pose).ToMatrix(), Eigen::Matrix3d::Identity()) <= kPoseTol);
    CHECK(MaxAbsDiff(pose.Inverse().ToMatrix(), pose.ToMatrix().inverse()) <= kPoseTol);
  }
}

TEST_CASE("SE2 Log returns plain x, y, yaw", "[pose]") {
  CHECK(MaxAbsDiff(SE2(1.5, -2.5, 0.75).Log(), Eigen::Vector3d(1.5, -2.5, 0.75)) <= kPoseTol);
}

TEST_CASE("SE2 interpolation hits the endpoints and takes the shorter yaw arc", "[pose]") {
  const SE2 a(0.0, 0.0, 2.9);
  const SE2 b(2.0, -4.0, -3.0);
  CHECK(MaxAbsDiff(SE2::Interpolate(a, b, 0.0).ToMatrix(), a.ToMatrix()) <= kPoseTol);
  CHECK(MaxAbsDiff(SE2::Interpolate(a, b, 1.0).ToMatrix(), b.ToMatrix()) <= kPoseTol);
  const SE2 middle = SE2::Interpolate(a, b, 0.5);
  CHECK(MaxAbsDiff(middle.translation(), Eigen::Vector2d(1.0, -2.0)) <= kPoseTol);
  // The short way from 2.9 to -3.0 crosses +-pi; the naive average would be -0.05.
  CHECK(middle.yaw() == Approx(NormalizeAngle(2.9 + 0.5 * (2.0 * kPi - 5.9))).margin(kPoseTol));
  CHECK(std::abs(middle.yaw()) > 3.0);
}

TEST_CASE("SE3 composition, point transform and matrix form agree", "[pose]") {
  const Eigen::Vector3d p(0.7, -1.3, 2.1);
  for (const SE3& a : SamplePoses3d()) {
    for (const SE3& b : SamplePoses3d()) {
      CHECK(MaxAbsDiff((a * b).ToMatrix(), a.ToMatrix() * b.ToMatrix()) <= kPoseTol);
      CHECK(MaxAbsDiff((a * b) * p, a * (b * p)) <= kPoseTol);
      CHECK(MaxAbsDiff(a * p, (a.ToMatrix() * p.homogeneous()).head<3>()) <= kPoseTol);
      CHECK(std::abs((a * b).quaternion().norm() - 1.0) <= kPoseTol);
    }
  }
}

TEST_CASE("SE3 times its inverse is the identity", "[pose]") {
  for (const SE3& pose : SamplePoses3d()) {
    CHECK(MaxAbsDiff((pose * pose.Inverse()).ToMatrix(), Eigen::Matrix4d::Identity()) <= kPoseTol);
    CHECK(MaxAbsDiff((pose.Inverse() * pose).ToMatrix(), Eigen::Matrix4d::Identity()) <= kPoseTol);
    CHECK(MaxAbsDiff(pose.Inverse().ToMatrix(), pose.ToMatrix().inverse()) <= kPoseTol);
  }
}

TEST_CASE("SE3 built from quaternion or rotation matrix is the same and normalised", "[pose]") {
  const Eigen::Quaterniond unnormalised(2.0, 0.4, -0.6, 1.0);
  const Eigen::Vector3d t(1.0, 2.0, 3.0);
  const SE3 from_quaternion(unnormalised, t);
  const SE3 from_matrix(unnormalised.normalized().toRotationMatrix(), t);
  CHECK(std::abs(from_quaternion.quaternion().norm() - 1.0) <= kPoseTol);
  CHECK(MaxAbsDiff(from_quaternion.ToMatrix(), from_matrix.ToMatrix()) <= kPoseTol);
  CHECK(MaxAbsDiff(from_quaternion.rotation(), unnormalised.normalized().toRotationMatrix()) <=
        kPoseTol);
}

TEST_CASE("SE3 from yaw, pitch, roll is Rz * Ry * Rx", "[pose]") {
  const double yaw = 0.4;
  const double pitch = -0.7;
  const double roll = 1.1;
  Eigen::Matrix3d rz, ry, rx;
  rz << std::cos(yaw), -std::sin(yaw), 0, std::sin(yaw), std::cos(yaw), 0, 0, 0, 1;
  ry << std::cos(pitch), 0, std::sin(pitch), 0, 1, 0, -std::sin(pitch), 0, std::cos(pitch);
  rx << 1, 0, 0, 0, std::cos(roll), -std::sin(roll), 0, std::sin(roll), std::cos(roll);
  const SE3 pose = SE3::FromYawPitchRoll(yaw, pitch, roll, Eigen::Vector3d(1, 2, 3));
  CHECK(MaxAbsDiff(pose.rotation(), rz * ry * rx) <= kPoseTol);
  CHECK(MaxAbsDiff(pose.translation(), Eigen::Vector3d(1, 2, 3)) <= kPoseTol);
  // Positive yaw turns +x towards +y.
  CHECK(MaxAbsDiff(SE3::FromYawPitchRoll(kPi / 2, 0, 0) * Eigen::Vector3d::UnitX(),
                   Eigen::Vector3d::UnitY()) <= kPoseTol);
}

TEST_CASE("SE2 lifted to SE3 rotates about +z and keeps composition", "[pose]") {
  const Eigen::Vector2d p(0.3, -0.8);
  for (const SE2& a : SamplePoses2d()) {
    const SE3 lifted = SE3::FromSE2(a, 1.25);
    INFO("pose = " << a.Log().transpose());
    const Eigen::Vector3d p_lifted = lifted * Eigen::Vector3d(p.x(), p.y(), 0.5);
    CHECK(MaxAbsDiff(p_lifted.head<2>(), a * p) <= kPoseTol);
    CHECK(p_lifted.z() == Approx(1.75).margin(kPoseTol));
    CHECK(MaxAbsDiff(lifted.rotation().topLeftCorner<2, 2>(), a.rotation()) <= kPoseTol);
    CHECK(MaxAbsDiff(lifted.rotation().col(2), Eigen::Vector3d::UnitZ()) <= kPoseTol);
    for (const SE2& b : SamplePoses2d()) {
      CHECK(MaxAbsDiff(SE3::FromSE2(a * b).ToMatrix(),
                       (SE3::FromSE2(a) * SE3::FromSE2(b)).ToMatrix()) <= kPoseTol);
    }
  }
}

TEST_CASE("SE3 interpolation hits the endpoints and slerps along the shorter arc", "[pose]") {
  const SE3 a = SE3::FromYawPitchRoll(0.2, 0.0, 0.0, Eigen::Vector3d(0, 0, 0));
  const SE3 b = SE3::FromYawPitchRoll(1.0, 0.0, 0.0, Eigen::Vector3d(2, 4, -6));
  CHECK(MaxAbsDiff(SE3::Interpolate(a, b, 0.0).ToMatrix(), a.ToMatrix()) <= kPoseTol);
  CHECK(MaxAbsDiff(SE3::Interpolate(a, b, 1.0).ToMatrix(), b.ToMatrix()) <= kPoseTol);
  const SE3 expected_middle = SE3::FromYawPitchRoll(0.6, 0.0, 0.0, Eigen::Vector3d(1, 2, -3));
  CHECK(MaxAbsDiff(SE3::Interpolate(a, b, 0.5).ToMatrix(), expected_middle.ToMatrix()) <= kPoseTol);
  // The same rotation given by the negated quaternion must interpolate the same way.
  const SE3 b_negated(Eigen::Quaterniond(-b.quaternion().coeffs()), b.translation());
  CHECK(MaxAbsDiff(SE3::Interpolate(a, b_negated, 0.5).ToMatrix(), expected_middle.ToMatrix()) <=
        kPoseTol);
}

}  // namespace
}  // namespace corridorsim
