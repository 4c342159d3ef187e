// slam/ekf/upward_models.cpp: the inverse-depth point landmark of the upward camera (P3 eq. 16,
// P2 eq. 7 through the real lens), its polar coordinates, its initialisation, and the analytic
// Jacobians against central differences.
#include "slam/ekf/upward_models.h"

#include <cmath>
#include <numbers>

#include <catch2/catch.hpp>

#include "tests/support/jacobian_check.h"
#include "tests/support/test_cameras.h"

namespace corridorsim {
namespace {

using slam::ekf::InverseDepthPoint;
using test::UpwardFisheye;
using test::UpwardMount;

TEST_CASE("upward model: the optical axis points up", "[ekf][upward]") {
  const SE3 mount = UpwardMount();
  CHECK((mount.rotation() * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitZ()).norm() < 1e-12);
}

TEST_CASE("upward model: an initialised landmark projects back to its pixel at any depth",
          "[ekf][upward]") {
  const CameraModel model = UpwardFisheye();
  const SE2 pose(1.2, -0.4, 0.7);
  for (const Eigen::Vector2d& pixel :
       {Eigen::Vector2d(100, 50), Eigen::Vector2d(330, 250), Eigen::Vector2d(600, 430)}) {
    for (const double rho : {0.2, 0.5, 2.0}) {
      const std::optional<InverseDepthPoint> l =
          slam::ekf::InitInverseDepthPoint(pose, pixel, rho, UpwardMount(), model, 0.1);
      REQUIRE(l);
      const std::optional<Eigen::Vector2d> back =
          slam::ekf::InverseDepthPixel(pose, *l, UpwardMount(), model);
      REQUIRE(back);
      CHECK((*back - pixel).norm() < 1e-6);
      // The world point lies 1 / rho above the camera.
      const Eigen::Vector3d p = slam::ekf::InverseDepthToPoint(*l, 0.4);
      CHECK(p.z() == Approx(0.4 + 1.0 / rho));
    }
  }
}

TEST_CASE("upward model: a pinhole at the robot's origin looking up is P3 eq. 16",
          "[ekf][upward]") {
  // The identity mount: optical axis (z) up, image x along the robot's x, image y along its y.
  const SE3 mount = SE3::Identity();
  const CameraModel pinhole = PinholeRadTan::FromFov(640, 480, 120.0 * std::numbers::pi / 180.0);
  const double f = pinhole.intrinsics().fx;
  const SE2 pose(2.0, 1.0, 0.3);
  const Eigen::Vector3d corner(3.1, 1.6, 2.5);
  // The landmark as inverse depth: anchored at the robot, ray to the corner.
  InverseDepthPoint l;
  l << pose.x(), pose.y(), (corner.x() - pose.x()) / corner.z(),
      (corner.y() - pose.y()) / corner.z(), 1.0 / corner.z();
  const std::optional<Eigen::Vector2d> polar =
      slam::ekf::InverseDepthPolar(pose, l, mount, pinhole);
  REQUIRE(polar);
  const double r_eq16 = std::hypot(corner.x() - pose.x(), corner.y() - pose.y()) * f / corner.z();
  const double theta_eq16 = std::atan2(corner.y() - pose.y(), corner.x() - pose.x()) - pose.yaw();
  CHECK((*polar)(0) == Approx(r_eq16).epsilon(1e-9));
  CHECK(std::remainder((*polar)(1) - theta_eq16, 2 * std::numbers::pi) == Approx(0).margin(1e-9));
}

TEST_CASE("upward model: analytic Jacobians match central differences", "[ekf][upward]") {
  const CameraModel model = UpwardFisheye();
  const SE3 mount = UpwardMount();
  const Eigen::Vector3d x0(0.8, -0.3, 0.9);
  InverseDepthPoint l;
  l << 0.5, 0.1, 0.4, -0.3, 0.45;
  Eigen::Matrix<double, 2, 3> d_pose;
  Eigen::Matrix<double, 2, 5> d_landmark;
  REQUIRE(slam::ekf::InverseDepthPolar(SE2(x0.x(), x0.y(), x0.z()), l, mount, model, &d_pose,
                                       &d_landmark));
  test::CheckPartialJacobians(
      [&](const Eigen::Vector3d& x, const InverseDepthPoint& y) {
        return *slam::ekf::InverseDepthPolar(SE2(x.x(), x.y(), x.z()), y, mount, model);
      },
      x0, l, d_pose, d_landmark);
  // Initialisation: over the pose and over (u, v, rho).
  const Eigen::Vector3d z0(250.0, 180.0, 0.6);
  Eigen::Matrix<double, 5, 3> a_pose, a_z;
  REQUIRE(slam::ekf::InitInverseDepthPoint(SE2(x0.x(), x0.y(), x0.z()), z0.head<2>(), z0(2), mount,
                                           model, 0.1, &a_pose, &a_z));
  test::CheckPartialJacobians(
      [&](const Eigen::Vector3d& x, const Eigen::Vector3d& z) {
        return *slam::ekf::InitInverseDepthPoint(SE2(x.x(), x.y(), x.z()), z.head<2>(), z(2), mount,
                                                 model, 0.1);
      },
      x0, z0, a_pose, a_z);
  Eigen::Matrix<double, 3, 5> d_point;
  slam::ekf::InverseDepthToPoint(l, 0.4, &d_point);
  test::CheckJacobian(
      d_point,
      test::NumericalJacobian<3, 5>(
          [&](const InverseDepthPoint& y) { return slam::ekf::InverseDepthToPoint(y, 0.4); }, l));
}

TEST_CASE("upward model: no projection for rho <= 0 or a ray pointing down", "[ekf][upward]") {
  const CameraModel model = UpwardFisheye();
  InverseDepthPoint l;
  l << 0, 0, 0.1, 0.1, 0.0;
  CHECK_FALSE(slam::ekf::InverseDepthPixel(SE2(), l, UpwardMount(), model));
  l(4) = -0.5;
  CHECK_FALSE(slam::ekf::InverseDepthPixel(SE2(), l, UpwardMount(), model));
  // A corner pixel of the 110 deg fisheye is 92 deg from the axis: below the horizon.
  CHECK_FALSE(slam::ekf::InitInverseDepthPoint(SE2(), {0.0, 0.0}, 0.5, UpwardMount(), model, 0.1));
}

TEST_CASE("door model: P3 eq. 17 from the camera centre, its inverse and Jacobians",
          "[ekf][upward][door]") {
  const Eigen::Vector2d camera_xy(-0.05, 0.0);
  const Eigen::Vector3d x0(1.0, 0.2, 0.3);
  const SE2 pose(x0.x(), x0.y(), x0.z());
  slam::ekf::DoorColumns door;
  door << 2.0, 1.2, 3.0, 1.2;
  Eigen::Matrix<double, 2, 3> d_pose;
  Eigen::Matrix<double, 2, 4> d_door;
  const std::optional<Eigen::Vector2d> b =
      slam::ekf::DoorBearings(pose, door, camera_xy, &d_pose, &d_door);
  REQUIRE(b);
  // By hand: the camera sits 5 cm behind the robot's origin along its heading.
  const Eigen::Vector2d c =
      Eigen::Vector2d(1.0, 0.2) - 0.05 * Eigen::Vector2d(std::cos(0.3), std::sin(0.3));
  CHECK((*b)(0) == Approx(std::atan2(1.2 - c.y(), 2.0 - c.x()) - 0.3).margin(1e-12));
  CHECK((*b)(1) == Approx(std::atan2(1.2 - c.y(), 3.0 - c.x()) - 0.3).margin(1e-12));
  test::CheckJacobian(d_pose, test::NumericalJacobian<2, 3>(
                                  [&](const Eigen::Vector3d& x) {
                                    return *slam::ekf::DoorBearings(SE2(x.x(), x.y(), x.z()), door,
                                                                    camera_xy);
                                  },
                                  x0));
  test::CheckJacobian(d_door, test::NumericalJacobian<2, 4>(
                                  [&](const Eigen::Vector4d& d) {
                                    return *slam::ekf::DoorBearings(pose, d, camera_xy);
                                  },
                                  door));
  // The inverse: bearings and ranges give the door back.
  const Eigen::Vector4d z((*b)(0), (*b)(1), (door.head<2>() - c).norm(),
                          (door.tail<2>() - c).norm());
  Eigen::Matrix<double, 4, 3> a_pose;
  Eigen::Matrix<double, 4, 4> a_z;
  CHECK((slam::ekf::DoorFromBearings(pose, z, camera_xy, &a_pose, &a_z) - door).norm() < 1e-12);
  test::CheckJacobian(a_pose, test::NumericalJacobian<4, 3>(
                                  [&](const Eigen::Vector3d& x) {
                                    return slam::ekf::DoorFromBearings(SE2(x.x(), x.y(), x.z()), z,
                                                                       camera_xy);
                                  },
                                  x0));
  test::CheckJacobian(a_z, test::NumericalJacobian<4, 4>(
                               [&](const Eigen::Vector4d& m) {
                                 return slam::ekf::DoorFromBearings(pose, m, camera_xy);
                               },
                               z));
  // A column on the camera centre has no bearing.
  slam::ekf::DoorColumns at_camera = door;
  at_camera.head<2>() = c;
  CHECK_FALSE(slam::ekf::DoorBearings(pose, at_camera, camera_xy));
}

}  // namespace
}  // namespace corridorsim
