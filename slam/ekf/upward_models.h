#pragma once
// Measurement models of the upward camera's landmarks (P2, P3): corners and lamps as points seen
// in polar image coordinates, doors as two column bearings. Pure functions with optional
// Jacobians, over the planar robot pose (x, y, yaw) as in measurement_models.h.
//
// The papers' corner and lamp model (P3 eq. 16, P2 eq. 7, the same but for P2's angle convention)
//   r     = sqrt((x_C - x_R)^2 + (y_C - y_R)^2) f_cam / z_C
//   theta = atan2(y_C - y_R, x_C - x_R) - theta_R
// is a pinhole camera at the robot's origin looking straight up, z_C the landmark's height above
// it: r = f tan(alpha) for the point's angle alpha from the axis. With the calibrated
// Kannala-Brandt lens the radius follows the lens instead: r = fx theta_d(alpha), theta_d the
// model's distorted angle (alpha itself for the equidistant lens of the default rig); the polar
// angle is that of the image point about the principal point, which is P3's theta up to the
// constant turn of the camera on its mount (the default rig's upward camera turns image x to the
// robot's -y). We use the exact projection through the camera's mount and model
// (UpwardPolar below) and convert its pixel to polar coordinates about the principal point:
//   r = |(u - c_x, v - c_y)|, theta = atan2(v - c_y, u - c_x).
// For a pinhole camera at the robot's origin, looking up with image x along the robot's x,
// this is P3 eq. 16 exactly (tests/slam/ekf/upward_models_test.cpp checks it).
//
// The landmark's parametrisation: inverse depth (Civera, Davison and Montiel 2008), anchored at
// the camera's height. A point first seen from the camera centre (x0, y0, z_cam) along the world
// ray (mx, my, 1) at an unknown height above the camera 1 / rho is
//   p = (x0 + mx / rho, y0 + my / rho, z_cam + 1 / rho),   state (x0, y0, mx, my, rho).
// Seen from a camera at c = (xc, yc, z_cam) (a planar robot keeps its camera's height), the
// direction to it scaled by rho > 0 is
//   g = (rho (x0 - xc) + mx, rho (y0 - yc) + my, 1),
// linear in rho: one sighting gives (x0, y0, mx, my) well and rho not at all, and the prior on
// rho (P3 section V: heights of 0-5 m) is Gaussian in rho, which the projection of g keeps close
// to linear over the whole prior. This is why it is used instead of a Gaussian on the height.

#include <optional>

#include <Eigen/Core>

#include "common/camera_models.h"
#include "common/pose.h"

namespace corridorsim::slam::ekf {

/// Inverse-depth point landmark: (x0, y0, mx, my, rho), see above.
using InverseDepthPoint = Eigen::Matrix<double, 5, 1>;

/// The camera centre's height above the floor for a mount (robot_from_camera's z).
double CameraHeight(const SE3& robot_from_camera);

/// The world point of an inverse-depth landmark (rho must be > 0), with its Jacobian.
Eigen::Vector3d InverseDepthToPoint(const InverseDepthPoint& landmark, double camera_height_m,
                                    Eigen::Matrix<double, 3, 5>* d_point_d_landmark = nullptr);

/// Polar image coordinates (r px, theta rad in (-pi, pi]) of a pixel about the model's
/// principal point, with the Jacobian d(r, theta) / d(u, v). r must be > 0.
Eigen::Vector2d PixelToPolar(const Eigen::Vector2d& pixel, const CameraModel& model,
                             Eigen::Matrix2d* d_polar_d_pixel = nullptr);

/// P3 eq. 16 / P2 eq. 7 through the real camera: the pixel of the inverse-depth landmark seen
/// from the pose, nullopt when it does not project (rho <= 0 puts it behind: the direction g
/// then points away from the point; outside the model's range). Jacobians over (x, y, yaw) and
/// over the landmark.
std::optional<Eigen::Vector2d> InverseDepthPixel(
    const SE2& world_from_robot, const InverseDepthPoint& landmark, const SE3& robot_from_camera,
    const CameraModel& model, Eigen::Matrix<double, 2, 3>* d_pixel_d_pose = nullptr,
    Eigen::Matrix<double, 2, 5>* d_pixel_d_landmark = nullptr);

/// The same as polar coordinates about the principal point (PixelToPolar of InverseDepthPixel).
std::optional<Eigen::Vector2d> InverseDepthPolar(
    const SE2& world_from_robot, const InverseDepthPoint& landmark, const SE3& robot_from_camera,
    const CameraModel& model, Eigen::Matrix<double, 2, 3>* d_polar_d_pose = nullptr,
    Eigen::Matrix<double, 2, 5>* d_polar_d_landmark = nullptr);

/// Initialisation (P3 section V): the landmark seen at `pixel` from the pose, with the prior
/// inverse depth `rho` (its uncertainty is the caller's measurement noise). Jacobians over the
/// pose and over (u, v, rho). nullopt when the pixel's ray does not point upwards (its world z
/// below `min_ray_z`, a unit ray: beyond acos(min_ray_z) from the vertical).
std::optional<InverseDepthPoint> InitInverseDepthPoint(
    const SE2& world_from_robot, const Eigen::Vector2d& pixel, double rho,
    const SE3& robot_from_camera, const CameraModel& model, double min_ray_z,
    Eigen::Matrix<double, 5, 3>* d_landmark_d_pose = nullptr,
    Eigen::Matrix<double, 5, 3>* d_landmark_d_measurement = nullptr);

/// A door landmark (P3 eq. 11): its columns' positions (x_D1, y_D1, x_D2, y_D2) on the floor plan.
using DoorColumns = Eigen::Vector4d;

/// The camera centre's position on the floor plan for the robot pose `pose` and the mount's
/// offset `camera_xy` (robot frame), with its Jacobian with respect to (x, y, yaw).
Eigen::Vector2d CameraXY(const SE2& pose, const Eigen::Vector2d& camera_xy,
                         Eigen::Matrix<double, 2, 3>* d_xy_d_pose = nullptr);

/// P3 eq. 17: the bearings of the two columns from the camera centre in the robot frame,
///   theta_Di = atan2(y_Di - y_C, x_Di - x_C) - theta_R  (wrapped to (-pi, pi]),
/// with the camera centre C in place of the robot's origin (the mount's offset), and the
/// Jacobians. nullopt when a column is at the camera centre.
std::optional<Eigen::Vector2d> DoorBearings(const SE2& pose, const DoorColumns& door,
                                            const Eigen::Vector2d& camera_xy,
                                            Eigen::Matrix<double, 2, 3>* d_pose = nullptr,
                                            Eigen::Matrix<double, 2, 4>* d_door = nullptr);

/// The inverse of DoorBearings given each column's horizontal range from the camera centre:
/// D_i = C + r_i (cos(theta_R + b_i), sin(theta_R + b_i)) for measurement (b_1, b_2, r_1, r_2),
/// with the Jacobians (for the augmentation of a registered door).
DoorColumns DoorFromBearings(const SE2& pose, const Eigen::Vector4d& bearings_and_ranges,
                             const Eigen::Vector2d& camera_xy,
                             Eigen::Matrix<double, 4, 3>* d_pose = nullptr,
                             Eigen::Matrix<double, 4, 4>* d_measurement = nullptr);

}  // namespace corridorsim::slam::ekf
