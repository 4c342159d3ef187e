// Tests slam/ekf/measurement_models.cpp: every Jacobian against central differences at random
// points, the derived forms of P1 eqs. 19 and 20 against the generic projection (and eq. 20's
// printed sign), and the inverse models as exact inverses of the forward ones.

#include "slam/ekf/measurement_models.h"

#include <cmath>
#include <numbers>

#include <catch2/catch.hpp>

#include "common/camera_models.h"
#include "common/pose.h"
#include "common/random.h"
#include "tests/support/jacobian_check.h"
#include "tests/support/test_cameras.h"
#include "tests/support/tolerances.h"

namespace corridorsim::slam::ekf {
namespace {

using Eigen::Matrix;
using Eigen::Vector2d;
using Eigen::Vector3d;
using test::CheckPartialJacobians;
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// The optical frame of a camera whose axis has heading `yaw` (0 forward, 90 deg left) and
// elevation `pitch` (rad) in the robot frame, at `t` (m): z along the axis, x to its right.
SE3 OpticalMount(double yaw, double pitch, const Vector3d& t) {
  const Vector3d z(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw),
                   std::sin(pitch));
  const Vector3d x(std::sin(yaw), -std::cos(yaw), 0.0);
  Eigen::Matrix3d r;
  r << x, z.cross(x), z;
  return SE3(r, t);
}

// The rig's defaults (render/camera_options.cpp): the front RGB-D sensor and the lateral camera.
SE3 FrontMount() { return OpticalMount(0.0, 0.0, Vector3d(0.18, 0.0, 0.45)); }
SE3 LateralMount() { return OpticalMount(90 * kDeg, 25 * kDeg, Vector3d(0.0, 0.12, 0.55)); }
CameraModel Front() { return PinholeRadTan::FromFov(640, 480, 58 * kDeg); }
CameraModel Lateral() { return PinholeRadTan::FromFov(640, 480, 60 * kDeg); }
CameraModel DistortedFront() {
  return test::WithWebcamDistortion(PinholeRadTan::FromFov(640, 480, 58 * kDeg));
}

SE2 PoseOf(const Vector3d& v) { return SE2(v[0], v[1], v[2]); }

Vector3d RandomPose(RandomStream& rng) {
  return Vector3d(rng.Uniform(-10, 10), rng.Uniform(-10, 10), rng.Uniform(-2.5, 2.5));
}

// A world point in front of the camera, well inside the field of view.
Vector3d RandomVisiblePoint(RandomStream& rng, const SE2& pose, const SE3& robot_from_camera,
                            double max_tan = 0.4) {
  const double depth = rng.Uniform(1.0, 8.0);
  const Vector3d p_in_camera(rng.Uniform(-max_tan, max_tan) * depth,
                             rng.Uniform(-max_tan, max_tan) * depth, depth);
  const Vector3d p_in_robot = robot_from_camera * p_in_camera;
  const Vector2d xy = pose * Vector2d(p_in_robot.head<2>());
  return Vector3d(xy.x(), xy.y(), p_in_robot.z());
}

TEST_CASE("ProjectWorldPoint and its depth form have the Jacobians of central differences",
          "[ekf_models]") {
  RandomStream rng(31, 0, "tests.ekf_models.project");
  const SE3 mount = LateralMount();
  const CameraModel model = DistortedFront();
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3d pose = RandomPose(rng);
    const Vector3d point = RandomVisiblePoint(rng, PoseOf(pose), mount);
    INFO("pose " << pose.transpose() << " point " << point.transpose());
    Matrix<double, 2, 3> d_pose, d_point;
    REQUIRE(ProjectWorldPoint(PoseOf(pose), point, mount, model, &d_pose, &d_point));
    CheckPartialJacobians(
        [&](const Vector3d& x, const Vector3d& p) {
          return *ProjectWorldPoint(PoseOf(x), p, mount, model);
        },
        pose, point, d_pose, d_point);
    Eigen::Matrix3d d3_pose, d3_point;
    const auto measured =
        ProjectWorldPointWithDepth(PoseOf(pose), point, mount, model, &d3_pose, &d3_point);
    REQUIRE(measured);
    CheckPartialJacobians(
        [&](const Vector3d& x, const Vector3d& p) {
          return *ProjectWorldPointWithDepth(PoseOf(x), p, mount, model);
        },
        pose, point, d3_pose, d3_point);
    CHECK(measured->head<2>() == *ProjectWorldPoint(PoseOf(pose), point, mount, model));
  }
}

TEST_CASE("a point behind the camera does not project", "[ekf_models]") {
  const SE2 pose(0.0, 0.0, 0.0);
  CHECK_FALSE(ProjectWorldPoint(pose, Vector3d(-3.0, 0.0, 0.45), FrontMount(), Front()));
  CHECK_FALSE(DoorPlateU(pose, Vector2d(0.5, -2.0), 1.6, LateralMount(), Lateral()));
}

TEST_CASE("VanishingPointU and DoorPlateU have the Jacobians of central differences",
          "[ekf_models]") {
  RandomStream rng(32, 0, "tests.ekf_models.u");
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3d pose = RandomPose(rng);
    const bool vp = trial % 2 == 0;
    const SE3 mount = vp ? FrontMount() : LateralMount();
    const CameraModel model = vp ? DistortedFront() : Lateral();
    const double height = vp ? mount.translation().z() : rng.Uniform(1.2, 2.0);
    const Vector3d p = RandomVisiblePoint(rng, PoseOf(pose), mount, 0.3);
    // A landmark (x, y) whose point at `height` is in front of the camera.
    const Vector3d in_camera =
        WorldPointInCamera(PoseOf(pose), Vector3d(p.x(), p.y(), height), mount);
    if (!(in_camera.z() > 0.5)) continue;
    const Vector2d landmark = p.head<2>();
    auto u_of = [&](const Vector3d& x, const Vector2d& l) {
      return vp ? VanishingPointU(PoseOf(x), l, mount, model)
                : DoorPlateU(PoseOf(x), l, height, mount, model);
    };
    Matrix<double, 1, 3> d_pose;
    Matrix<double, 1, 2> d_landmark;
    const std::optional<double> u =
        vp ? VanishingPointU(PoseOf(pose), landmark, mount, model, &d_pose, &d_landmark)
           : DoorPlateU(PoseOf(pose), landmark, height, mount, model, &d_pose, &d_landmark);
    REQUIRE(u);
    INFO("pose " << pose.transpose() << " landmark " << landmark.transpose());
    CheckPartialJacobians(
        [&](const Vector3d& x, const Vector2d& l) { return Matrix<double, 1, 1>(*u_of(x, l)); },
        pose, landmark, d_pose, d_landmark);
  }
}

// The robot-frame coordinates of a planar landmark (ahead X_R, left Y_R).
Vector2d InRobot(const SE2& pose, const Vector2d& landmark) { return pose.Inverse() * landmark; }

TEST_CASE("the derived forms of P1 eqs. 19 and 20 are the generic projection", "[ekf_models]") {
  // Cameras at the robot's origin (at height h), level, undistorted: the header's derivation.
  const double h = 0.5;
  const SE3 front = OpticalMount(0.0, 0.0, Vector3d(0.0, 0.0, h));
  const SE3 left = OpticalMount(90 * kDeg, 0.0, Vector3d(0.0, 0.0, h));
  const PinholeRadTan pinhole = PinholeRadTan::FromFov(640, 480, 60 * kDeg);
  const double f = pinhole.fx;
  const double cx = pinhole.cx;
  RandomStream rng(33, 0, "tests.ekf_models.derived");
  for (int trial = 0; trial < 30; ++trial) {
    const SE2 pose = PoseOf(RandomPose(rng));
    // A VP 30 m ahead, within 10 deg of the axis; a plate 1-3 m to the left, +-1 m along.
    const double bearing = rng.Uniform(-10, 10) * kDeg;
    const Vector2d vp = pose * Vector2d(30 * std::cos(bearing), 30 * std::sin(bearing));
    const Vector2d plate = pose * Vector2d(rng.Uniform(-1, 1), rng.Uniform(1, 3));
    const double phi = pose.yaw();
    const double dxv = vp.x() - pose.x(), dyv = vp.y() - pose.y();
    const double dxd = plate.x() - pose.x(), dyd = plate.y() - pose.y();
    // u_front = f (-Y_R) / X_R, u_left = f X_R / Y_R.
    const double x_r_v = dxv * std::cos(phi) + dyv * std::sin(phi);
    const double u_front = cx + f * (dxv * std::sin(phi) - dyv * std::cos(phi)) / x_r_v;
    const Vector2d plate_r = InRobot(pose, plate);
    const double u_left = cx + f * (dxd * std::cos(phi) + dyd * std::sin(phi)) / plate_r.y();
    CHECK(*VanishingPointU(pose, vp, front, pinhole) == Approx(u_front).margin(test::kRoundTripPx));
    CHECK(*DoorPlateU(pose, plate, h, left, pinhole) == Approx(u_left).margin(test::kRoundTripPx));
    // Eq. 19 divides by the range (sine of the bearing for its tangent): close for a far VP.
    const double eq19 = cx + f * (dxv * std::sin(phi) - dyv * std::cos(phi)) / std::hypot(dxv, dyv);
    CHECK(std::abs(eq19 - u_front) <= f * std::abs(std::tan(bearing) - std::sin(bearing)) + 1e-9);
  }
}

// P1 eq. 20 as printed (u from the principal point) and with the sine's sign corrected.
double Eq20Printed(const SE2& pose, const Vector2d& plate, double f) {
  const double phi = pose.yaw();
  return f * ((pose.x() - plate.x()) * std::cos(phi) - (pose.y() - plate.y()) * std::sin(phi)) /
         (plate - pose.translation()).norm();
}
double Eq20Corrected(const SE2& pose, const Vector2d& plate, double f) {
  const double phi = pose.yaw();
  return f * ((pose.x() - plate.x()) * std::cos(phi) + (pose.y() - plate.y()) * std::sin(phi)) /
         (plate - pose.translation()).norm();
}

TEST_CASE("P1 eq. 20 as printed has the wrong sign", "[ekf_models]") {
  const double h = 0.5;
  const SE3 left = OpticalMount(90 * kDeg, 0.0, Vector3d(0.0, 0.0, h));
  const PinholeRadTan pinhole = PinholeRadTan::FromFov(640, 480, 60 * kDeg);
  const double f = pinhole.fx;
  // Robot at the origin facing +x, plate 1 m ahead and 2 m to the left.
  const SE2 pose(0.0, 0.0, 0.0);
  const Vector2d plate(1.0, 2.0);
  const double u = *DoorPlateU(pose, plate, h, left, pinhole);
  CHECK(u > pinhole.cx);                     // the left camera sees "ahead" on its right
  CHECK(Eq20Printed(pose, plate, f) < 0.0);  // eq. 20 puts it left of the centre
  // Turning robot and plate together by 90 deg changes nothing the robot sees ...
  const SE2 turn(0.0, 0.0, kPi / 2);
  const SE2 turned_pose = turn * pose;
  const Vector2d turned_plate = turn * plate;
  CHECK(*DoorPlateU(turned_pose, turned_plate, h, left, pinhole) ==
        Approx(u).margin(test::kRoundTripPx));
  CHECK(Eq20Corrected(turned_pose, turned_plate, f) ==
        Approx(Eq20Corrected(pose, plate, f)).margin(1e-9));
  // ... but flips the printed form's sign: its sine term has the wrong sign.
  CHECK(Eq20Printed(turned_pose, turned_plate, f) ==
        Approx(-Eq20Printed(pose, plate, f)).margin(1e-9));
  // The corrected form is -f X_R / range: the pinhole's u mirrored, to first order.
  const Vector2d plate_r = InRobot(pose, plate);
  CHECK(Eq20Corrected(pose, plate, f) == Approx(-f * plate_r.x() / plate_r.norm()).margin(1e-9));
}

TEST_CASE("InitVanishingPoint inverts VanishingPointU and has central-difference Jacobians",
          "[ekf_models]") {
  RandomStream rng(34, 0, "tests.ekf_models.vp_init");
  for (int trial = 0; trial < 40; ++trial) {
    const Vector3d pose = RandomPose(rng);
    // The front camera, level; every fourth trial pitched (the inverse is exact for any pitch).
    const SE3 mount =
        trial % 4 == 3 ? OpticalMount(5 * kDeg, 10 * kDeg, Vector3d(0.2, 0.05, 0.4)) : FrontMount();
    const CameraModel model = Front();
    const double u = rng.Uniform(100, 540);
    const double distance = rng.Uniform(10, 50);
    Matrix<double, 2, 3> d_pose;
    Vector2d d_u;
    const auto vp = InitVanishingPoint(PoseOf(pose), u, distance, mount, model, &d_pose, &d_u);
    REQUIRE(vp);
    INFO("pose " << pose.transpose() << " u " << u);
    CHECK(*VanishingPointU(PoseOf(pose), *vp, mount, model) == Approx(u).margin(1e-7));
    const Vector3d centre_in_robot = mount.translation();
    const Vector2d centre = PoseOf(pose) * Vector2d(centre_in_robot.head<2>());
    CHECK((*vp - centre).norm() == Approx(distance).epsilon(1e-12));
    CheckPartialJacobians(
        [&](const Vector3d& x, const Matrix<double, 1, 1>& v) {
          return *InitVanishingPoint(PoseOf(x), v[0], distance, mount, model);
        },
        pose, Matrix<double, 1, 1>(u), d_pose, d_u);
  }
}

TEST_CASE("TriangulateDoorPlate recovers the plate from two sightings, with its Jacobians",
          "[ekf_models]") {
  RandomStream rng(35, 0, "tests.ekf_models.triangulate");
  const SE3 mount = LateralMount();
  const CameraModel model = Lateral();
  int checked = 0;
  for (int trial = 0; trial < 60; ++trial) {
    // The robot drives 0.3-1.5 m along its heading past a plate 1-2.5 m to its left.
    const Vector3d first = RandomPose(rng);
    const double travel = rng.Uniform(0.3, 1.5);
    const Vector3d second(first[0] + travel * std::cos(first[2]),
                          first[1] + travel * std::sin(first[2]),
                          first[2] + rng.Uniform(-0.1, 0.1));
    const double height = rng.Uniform(1.4, 1.8);
    const Vector2d plate =
        PoseOf(first) * Vector2d(rng.Uniform(0.0, travel), rng.Uniform(1.0, 2.5));
    const auto u1 = DoorPlateU(PoseOf(first), plate, height, mount, model);
    const auto u2 = DoorPlateU(PoseOf(second), plate, height, mount, model);
    if (!u1 || !u2) continue;
    Matrix<double, 2, 3> d_first, d_second;
    Vector2d d_u1, d_u2;
    const auto t = TriangulateDoorPlate(PoseOf(first), *u1, PoseOf(second), *u2, height, mount,
                                        model, &d_first, &d_u1, &d_second, &d_u2);
    REQUIRE(t);
    INFO("first " << first.transpose() << " second " << second.transpose() << " plate "
                  << plate.transpose());
    CHECK((t->plate_in_world - plate).norm() <= 1e-9);
    // The parallax: the angle at the plate between the rays to the two camera centres.
    const Vector3d p3(plate.x(), plate.y(), height);
    auto centre = [&](const Vector3d& pose) {
      const Vector2d c = PoseOf(pose) * Vector2d(mount.translation().head<2>());
      return Vector3d(c.x(), c.y(), mount.translation().z());
    };
    const Vector3d a = (centre(first) - p3).normalized(), b = (centre(second) - p3).normalized();
    CHECK(t->parallax_rad == Approx(std::acos(a.dot(b))).margin(1e-7));
    auto solve = [&](const Vector3d& p1, double v1, const Vector3d& p2, double v2) {
      return TriangulateDoorPlate(PoseOf(p1), v1, PoseOf(p2), v2, height, mount, model)
          ->plate_in_world;
    };
    CheckPartialJacobians(
        [&](const Vector3d& p1, const Vector3d& p2) { return solve(p1, *u1, p2, *u2); }, first,
        second, d_first, d_second);
    CheckPartialJacobians(
        [&](const Matrix<double, 1, 1>& v1, const Matrix<double, 1, 1>& v2) {
          return solve(first, v1[0], second, v2[0]);
        },
        Matrix<double, 1, 1>(*u1), Matrix<double, 1, 1>(*u2), d_u1, d_u2);
    ++checked;
  }
  CHECK(checked >= 30);
  // The same sighting twice: parallel lines, no plate.
  const SE2 pose(1.0, 2.0, 0.3);
  const double u = *DoorPlateU(pose, pose * Vector2d(0.2, 1.5), 1.6, mount, model);
  CHECK_FALSE(TriangulateDoorPlate(pose, u, pose, u, 1.6, mount, model));
}

TEST_CASE("UnprojectRgbdPoint inverts the depth projection and has central-difference Jacobians",
          "[ekf_models]") {
  RandomStream rng(36, 0, "tests.ekf_models.rgbd");
  const SE3 mount = FrontMount();
  const CameraModel model = DistortedFront();
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3d pose = RandomPose(rng);
    const Vector3d point = RandomVisiblePoint(rng, PoseOf(pose), mount, 0.3);
    const Vector3d z = *ProjectWorldPointWithDepth(PoseOf(pose), point, mount, model);
    Eigen::Matrix3d d_pose, d_z;
    const auto back = UnprojectRgbdPoint(PoseOf(pose), z, mount, model, &d_pose, &d_z);
    REQUIRE(back);
    INFO("pose " << pose.transpose() << " point " << point.transpose());
    CHECK((*back - point).norm() <= 1e-8);
    CheckPartialJacobians(
        [&](const Vector3d& x, const Vector3d& m) {
          return *UnprojectRgbdPoint(PoseOf(x), m, mount, model);
        },
        pose, z, d_pose, d_z);
  }
  CHECK_FALSE(UnprojectRgbdPoint(SE2(), Vector3d(320, 240, 0.0), mount, model));
}

TEST_CASE("range-bearing and its inverse have central-difference Jacobians", "[ekf_models]") {
  RandomStream rng(37, 0, "tests.ekf_models.range_bearing");
  for (int trial = 0; trial < 50; ++trial) {
    const Vector3d pose = RandomPose(rng);
    // Bearings within +-150 deg (away from the wrap at pi).
    const Vector2d z_true(rng.Uniform(0.5, 20), rng.Uniform(-2.6, 2.6));
    const Vector2d landmark = RangeBearingInverse(PoseOf(pose), z_true);
    Matrix<double, 2, 3> d_pose;
    Eigen::Matrix2d d_landmark;
    const Vector2d z = RangeBearing(PoseOf(pose), landmark, &d_pose, &d_landmark);
    CHECK((z - z_true).norm() <= 1e-9);
    CheckPartialJacobians(
        [&](const Vector3d& x, const Vector2d& l) { return RangeBearing(PoseOf(x), l); }, pose,
        landmark, d_pose, d_landmark);
    Matrix<double, 2, 3> d_inv_pose;
    Eigen::Matrix2d d_inv_z;
    RangeBearingInverse(PoseOf(pose), z_true, &d_inv_pose, &d_inv_z);
    CheckPartialJacobians(
        [&](const Vector3d& x, const Vector2d& m) { return RangeBearingInverse(PoseOf(x), m); },
        pose, z_true, d_inv_pose, d_inv_z);
  }
}

}  // namespace
}  // namespace corridorsim::slam::ekf
