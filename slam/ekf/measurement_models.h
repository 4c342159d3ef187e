#pragma once
// Measurement models of the EKF landmarks (STYLE item 5): pure functions with optional Jacobian
// outputs. The robot pose is planar, `world_from_robot` = (x m, y m, yaw rad), Jacobians "d_pose"
// over those plain parameters in that order (the yaw derivative is that of the unwrapped angle).
// The robot frame R has x forward, y left, z up with z = 0 on the floor; a camera is mounted by
// `robot_from_camera` (the OpenCV optical frame: x right, y down, z forward) and projects with a
// CameraModel (common/camera_models.h).
//
// P1's models (eqs. 19 and 20) and what we use instead
// ----------------------------------------------------
// P1 writes the vanishing point (VP, landmark l_v = (x_v, y_v) on a virtual plane ahead) and the
// door plate (landmark l_d = (x_d, y_d)) as the u coordinate of their image, the robot at
// (x_r, y_r, phi):
//   eq. 19:  u_v = f_v {(x_v - x_r) sin phi - (y_v - y_r) cos phi} / sqrt((x_v - x_r)^2 + (y_v -
//   y_r)^2) eq. 20:  u_d = f_d {(x_r - x_d) cos phi - (y_r - y_d) sin phi} / sqrt((x_d - x_r)^2 +
//   (y_d - y_r)^2)
// Derivation, a camera at the robot's origin, u measured from the principal point: the landmark
// in the robot frame is
//   X_R =  (x - x_r) cos phi + (y - y_r) sin phi      (ahead)
//   Y_R = -(x - x_r) sin phi + (y - y_r) cos phi      (to the left)
// A camera facing forward has optical x = -y_R and z = x_R, so the pinhole gives
//   u_front = f (-Y_R) / X_R = f {(x - x_r) sin phi - (y - y_r) cos phi} / X_R,
// eq. 19's numerator exactly; eq. 19 divides by the range sqrt(X_R^2 + Y_R^2) instead of the depth
// X_R, i.e. it takes the sine of the bearing where the pinhole has its tangent (equal to first
// order in the bearing, which is small for a VP far ahead).
// A camera facing left (+y of the robot, as the lateral camera here) has optical z = y_R and
// x = x_R (the image's right is the robot's front), so
//   u_left = f X_R / Y_R = f {(x - x_r) cos phi + (y - y_r) sin phi} / Y_R
//          = -f {(x_r - x) cos phi + (y_r - y) sin phi} / Y_R,
// and one facing right (-y) has u_right = -u_left = f {(x_r - x) cos phi + (y_r - y) sin phi} /
// (-Y_R). So the sine term of eq. 20 must carry a PLUS sign: f_d {(x_r - x_d) cos phi + (y_r - y_d)
// sin phi} is -f_d X_R (P1's form for a camera facing right, or facing left with u counted
// leftwards), which like eq. 19 depends on the landmark in the robot frame only. As printed, with
// the minus, it is not a function of the robot-frame landmark at all: rotating the robot and the
// plate together about the origin changes it (at phi = 0 it reads -f_d X_R / range, at phi = pi/2
// it reads +f_d X_R / range), and it disagrees with eq. 19's form. We do not use either formula:
// the models below are the exact pinhole projection through the camera's real mount and model
// (ProjectWorldPoint), which equal eqs. 19/20 with the corrected sign (and P1's sign convention
// of u) for a camera at the robot's origin and small bearings.
// tests/slam/ekf/measurement_models_test.cpp shows it: the derived u_front and u_left equal
// ProjectWorldPoint; eq. 20 as printed flips sign when robot and plate turn together by 90 deg
// (the corrected form does not); and for the left-facing camera P1's u is mirrored: a plate
// ahead-left of a robot facing +x projects right of the image centre, eq. 20 puts it left.

#include <optional>

#include <Eigen/Core>

#include "common/camera_models.h"
#include "common/pose.h"

namespace corridorsim::slam::ekf {

/// p_in_camera of the world point `p_in_world` (m) seen from the planar pose through the mount:
/// camera_from_robot * robot_from_world * p_in_world, with Jacobians over (x, y, yaw) and over
/// p_in_world.
Eigen::Vector3d WorldPointInCamera(const SE2& world_from_robot, const Eigen::Vector3d& p_in_world,
                                   const SE3& robot_from_camera,
                                   Eigen::Matrix3d* d_point_d_pose = nullptr,
                                   Eigen::Matrix3d* d_point_d_world_point = nullptr);

/// The generic camera landmark model: the pixel of `p_in_world` (px), nullopt when the model does
/// not project it (behind the camera, outside the valid range). Pixels outside the image are
/// returned (the caller decides what is visible).
std::optional<Eigen::Vector2d> ProjectWorldPoint(
    const SE2& world_from_robot, const Eigen::Vector3d& p_in_world, const SE3& robot_from_camera,
    const CameraModel& model, Eigen::Matrix<double, 2, 3>* d_pixel_d_pose = nullptr,
    Eigen::Matrix<double, 2, 3>* d_pixel_d_point = nullptr);

/// The RGB-D measurement (u px, v px, depth m = z in the camera) of `p_in_world`, for the Harris
/// point baseline; nullopt where ProjectWorldPoint gives none.
std::optional<Eigen::Vector3d> ProjectWorldPointWithDepth(
    const SE2& world_from_robot, const Eigen::Vector3d& p_in_world, const SE3& robot_from_camera,
    const CameraModel& model, Eigen::Matrix3d* d_measurement_d_pose = nullptr,
    Eigen::Matrix3d* d_measurement_d_point = nullptr);

/// P1 eq. 19, exact form: u (px) of the VP landmark (x_v, y_v) (world, m), a point of the virtual
/// plane placed at the camera's height (robot_from_camera's z), seen by the front camera.
std::optional<double> VanishingPointU(const SE2& world_from_robot,
                                      const Eigen::Vector2d& vp_in_world,
                                      const SE3& robot_from_camera, const CameraModel& model,
                                      Eigen::Matrix<double, 1, 3>* d_u_d_pose = nullptr,
                                      Eigen::Matrix<double, 1, 2>* d_u_d_landmark = nullptr);

/// P1 eq. 20 (first row), exact form: u (px) of the door plate (x_d, y_d) (world, m), taken at
/// the nominal height `plate_height_m` above the floor, seen by the lateral camera.
std::optional<double> DoorPlateU(const SE2& world_from_robot, const Eigen::Vector2d& plate_in_world,
                                 double plate_height_m, const SE3& robot_from_camera,
                                 const CameraModel& model,
                                 Eigen::Matrix<double, 1, 3>* d_u_d_pose = nullptr,
                                 Eigen::Matrix<double, 1, 2>* d_u_d_landmark = nullptr);

// Inverse models for augmentation (P1 eqs. 26-27: A = d_landmark_d_pose, A_a = d_landmark_d_u).
// A measured u fixes a plane through the camera centre: the image column u (for an undistorted
// pinhole exactly; with distortion, the column through the principal row, v = cy). The VP and the
// plate are points of that plane at a known height, so both inverses are exact inverses of
// VanishingPointU and DoorPlateU for an undistorted pinhole, whatever the camera's pitch.

/// P1 Fig. 10: the VP landmark for a measured `u` (px): the point of the column's plane at the
/// camera's height, `virtual_distance_m` (> 0) from the camera, in front of it. nullopt when the
/// column's plane is horizontal (no such point) or u does not unproject in front of the camera.
std::optional<Eigen::Vector2d> InitVanishingPoint(
    const SE2& world_from_robot, double u, double virtual_distance_m, const SE3& robot_from_camera,
    const CameraModel& model, Eigen::Matrix<double, 2, 3>* d_landmark_d_pose = nullptr,
    Eigen::Vector2d* d_landmark_d_u = nullptr);

/// A door plate triangulated from two sightings by the lateral camera.
struct PlateTriangulation {
  Eigen::Vector2d plate_in_world;  // (x_d, y_d), m, world frame
  double parallax_rad = 0.0;       // angle at the plate (at its nominal height) between the rays
                                   // to the two camera centres: wait until it is large enough
};

/// Delayed initialisation: the plate (x, y) at `plate_height_m` whose image columns are `u_first`
/// from `world_from_robot_first` (a pose clone of the first sighting) and `u_second` from
/// `world_from_robot_second` (the current pose): the intersection of the two columns' lines at the
/// plate's height. nullopt when the lines are (nearly) parallel or the point is not in front of
/// both cameras. Jacobians (optional) over both poses (2x3 each) and both u's (2x1 each).
std::optional<PlateTriangulation> TriangulateDoorPlate(
    const SE2& world_from_robot_first, double u_first, const SE2& world_from_robot_second,
    double u_second, double plate_height_m, const SE3& robot_from_camera, const CameraModel& model,
    Eigen::Matrix<double, 2, 3>* d_plate_d_pose_first = nullptr,
    Eigen::Vector2d* d_plate_d_u_first = nullptr,
    Eigen::Matrix<double, 2, 3>* d_plate_d_pose_second = nullptr,
    Eigen::Vector2d* d_plate_d_u_second = nullptr);

/// The Harris baseline's inverse: p_in_world of the RGB-D measurement (u px, v px, depth m = z in
/// the camera). nullopt for depth <= 0 or a pixel whose bearing is not in front (z <= 0).
std::optional<Eigen::Vector3d> UnprojectRgbdPoint(const SE2& world_from_robot,
                                                  const Eigen::Vector3d& pixel_and_depth,
                                                  const SE3& robot_from_camera,
                                                  const CameraModel& model,
                                                  Eigen::Matrix3d* d_point_d_pose = nullptr,
                                                  Eigen::Matrix3d* d_point_d_measurement = nullptr);

/// Range (m) and bearing (rad, from the robot's heading, counter-clockwise, in (-pi, pi]) of the
/// planar point `landmark_in_world`; for bench_ekf and the EKF's consistency test. The landmark
/// must not sit on the robot (range 0: the bearing is undefined).
Eigen::Vector2d RangeBearing(const SE2& world_from_robot, const Eigen::Vector2d& landmark_in_world,
                             Eigen::Matrix<double, 2, 3>* d_z_d_pose = nullptr,
                             Eigen::Matrix2d* d_z_d_landmark = nullptr);

/// The inverse: the landmark at (range, bearing) from the pose.
Eigen::Vector2d RangeBearingInverse(const SE2& world_from_robot,
                                    const Eigen::Vector2d& range_bearing,
                                    Eigen::Matrix<double, 2, 3>* d_landmark_d_pose = nullptr,
                                    Eigen::Matrix2d* d_landmark_d_z = nullptr);

}  // namespace corridorsim::slam::ekf
