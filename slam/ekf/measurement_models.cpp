#include "slam/ekf/measurement_models.h"

#include <cmath>

#include "common/error.h"

namespace corridorsim::slam::ekf {
namespace {

// Counter-clockwise quarter turn of a planar vector: d R(yaw) / d yaw = Perp * R(yaw).
Eigen::Vector2d Perp(const Eigen::Vector2d& v) { return Eigen::Vector2d(-v.y(), v.x()); }

double PrincipalRow(const CameraModel& model) {
  return model.pinhole() != nullptr ? model.pinhole()->cy : model.kannala_brandt()->cy;
}

// The plane of the image column u through the camera centre, {p_in_robot : n . (p - c) = 0}:
// the camera's normalised x = X / Z of the column (at the principal row) is fixed, so
// n_in_camera = (1, 0, -x_n(u)). Its normal in the robot frame and d n / d u.
struct ColumnPlane {
  Eigen::Vector3d normal_in_robot;
  Eigen::Vector3d d_normal_d_u;
};

std::optional<ColumnPlane> ColumnPlaneOf(double u, const SE3& robot_from_camera,
                                         const CameraModel& model) {
  if (!std::isfinite(u)) return std::nullopt;
  Eigen::Matrix<double, 3, 2> d_bearing_d_pixel;
  const Eigen::Vector3d bearing =
      model.Unproject(Eigen::Vector2d(u, PrincipalRow(model)), &d_bearing_d_pixel);
  if (!(bearing.z() > 1e-9)) return std::nullopt;
  const double x_n = bearing.x() / bearing.z();
  const double d_x_n_d_u =
      (d_bearing_d_pixel(0, 0) * bearing.z() - bearing.x() * d_bearing_d_pixel(2, 0)) /
      (bearing.z() * bearing.z());
  const Eigen::Matrix3d robot_r_camera = robot_from_camera.rotation();
  return ColumnPlane{robot_r_camera * Eigen::Vector3d(1.0, 0.0, -x_n),
                     robot_r_camera * Eigen::Vector3d(0.0, 0.0, -d_x_n_d_u)};
}

}  // namespace

Eigen::Vector3d WorldPointInCamera(const SE2& world_from_robot, const Eigen::Vector3d& p_in_world,
                                   const SE3& robot_from_camera, Eigen::Matrix3d* d_point_d_pose,
                                   Eigen::Matrix3d* d_point_d_world_point) {
  const Eigen::Matrix2d world_r_robot = world_from_robot.rotation();
  // Planar pose: p_in_robot = (R^T (p_xy - t), p_z), the floor at z = 0 in both frames.
  Eigen::Vector3d p_in_robot;
  p_in_robot.head<2>() =
      world_r_robot.transpose() * (p_in_world.head<2>() - world_from_robot.translation());
  p_in_robot.z() = p_in_world.z();
  const Eigen::Matrix3d camera_r_robot = robot_from_camera.rotation().transpose();
  const Eigen::Vector3d p_in_camera =
      camera_r_robot * (p_in_robot - robot_from_camera.translation());
  if (d_point_d_pose != nullptr) {
    Eigen::Matrix3d d_robot_d_pose = Eigen::Matrix3d::Zero();
    d_robot_d_pose.topLeftCorner<2, 2>() = -world_r_robot.transpose();
    // d (R(yaw)^T v) / d yaw = -R^T Perp v = (p_y, -p_x) in the robot frame.
    d_robot_d_pose.block<2, 1>(0, 2) = Eigen::Vector2d(p_in_robot.y(), -p_in_robot.x());
    *d_point_d_pose = camera_r_robot * d_robot_d_pose;
  }
  if (d_point_d_world_point != nullptr) {
    Eigen::Matrix3d d_robot_d_world = Eigen::Matrix3d::Identity();
    d_robot_d_world.topLeftCorner<2, 2>() = world_r_robot.transpose();
    *d_point_d_world_point = camera_r_robot * d_robot_d_world;
  }
  return p_in_camera;
}

namespace {

// A world point through the camera: its camera-frame position, its pixel and the Jacobians both
// projections share (pixel by camera point; camera point by pose and by world point).
struct CameraProjection {
  Eigen::Vector3d p_in_camera;
  Eigen::Vector2d pixel;
  // Zero where the caller asked for no Jacobians.
  Eigen::Matrix<double, 2, 3> d_pixel_d_camera = Eigen::Matrix<double, 2, 3>::Zero();
  Eigen::Matrix3d d_camera_d_pose = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d d_camera_d_point = Eigen::Matrix3d::Zero();
};

std::optional<CameraProjection> ProjectThroughCamera(const SE2& world_from_robot,
                                                     const Eigen::Vector3d& p_in_world,
                                                     const SE3& robot_from_camera,
                                                     const CameraModel& model, bool jacobians) {
  CameraProjection p;
  p.p_in_camera = WorldPointInCamera(world_from_robot, p_in_world, robot_from_camera,
                                     jacobians ? &p.d_camera_d_pose : nullptr,
                                     jacobians ? &p.d_camera_d_point : nullptr);
  const std::optional<Eigen::Vector2d> pixel =
      model.Project(p.p_in_camera, jacobians ? &p.d_pixel_d_camera : nullptr);
  if (!pixel) return std::nullopt;
  p.pixel = *pixel;
  return p;
}

}  // namespace

std::optional<Eigen::Vector2d> ProjectWorldPoint(const SE2& world_from_robot,
                                                 const Eigen::Vector3d& p_in_world,
                                                 const SE3& robot_from_camera,
                                                 const CameraModel& model,
                                                 Eigen::Matrix<double, 2, 3>* d_pixel_d_pose,
                                                 Eigen::Matrix<double, 2, 3>* d_pixel_d_point) {
  const bool jacobians = d_pixel_d_pose != nullptr || d_pixel_d_point != nullptr;
  const std::optional<CameraProjection> p =
      ProjectThroughCamera(world_from_robot, p_in_world, robot_from_camera, model, jacobians);
  if (!p) return std::nullopt;
  if (d_pixel_d_pose != nullptr) *d_pixel_d_pose = p->d_pixel_d_camera * p->d_camera_d_pose;
  if (d_pixel_d_point != nullptr) *d_pixel_d_point = p->d_pixel_d_camera * p->d_camera_d_point;
  return p->pixel;
}

std::optional<Eigen::Vector3d> ProjectWorldPointWithDepth(const SE2& world_from_robot,
                                                          const Eigen::Vector3d& p_in_world,
                                                          const SE3& robot_from_camera,
                                                          const CameraModel& model,
                                                          Eigen::Matrix3d* d_measurement_d_pose,
                                                          Eigen::Matrix3d* d_measurement_d_point) {
  const bool jacobians = d_measurement_d_pose != nullptr || d_measurement_d_point != nullptr;
  const std::optional<CameraProjection> p =
      ProjectThroughCamera(world_from_robot, p_in_world, robot_from_camera, model, jacobians);
  if (!p) return std::nullopt;
  Eigen::Matrix3d d_measurement_d_camera;
  d_measurement_d_camera.topRows<2>() = p->d_pixel_d_camera;
  d_measurement_d_camera.row(2) = Eigen::RowVector3d(0.0, 0.0, 1.0);  // depth = z in the camera
  if (d_measurement_d_pose != nullptr) {
    *d_measurement_d_pose = d_measurement_d_camera * p->d_camera_d_pose;
  }
  if (d_measurement_d_point != nullptr) {
    *d_measurement_d_point = d_measurement_d_camera * p->d_camera_d_point;
  }
  return Eigen::Vector3d(p->pixel.x(), p->pixel.y(), p->p_in_camera.z());
}

std::optional<double> VanishingPointU(const SE2& world_from_robot,
                                      const Eigen::Vector2d& vp_in_world,
                                      const SE3& robot_from_camera, const CameraModel& model,
                                      Eigen::Matrix<double, 1, 3>* d_u_d_pose,
                                      Eigen::Matrix<double, 1, 2>* d_u_d_landmark) {
  // P1 eq. 19 (exact form, see the header): the virtual-plane point at the camera's height.
  return DoorPlateU(world_from_robot, vp_in_world, robot_from_camera.translation().z(),
                    robot_from_camera, model, d_u_d_pose, d_u_d_landmark);
}

std::optional<double> DoorPlateU(const SE2& world_from_robot, const Eigen::Vector2d& plate_in_world,
                                 double plate_height_m, const SE3& robot_from_camera,
                                 const CameraModel& model, Eigen::Matrix<double, 1, 3>* d_u_d_pose,
                                 Eigen::Matrix<double, 1, 2>* d_u_d_landmark) {
  // P1 eq. 20, first row (exact form, see the header).
  const bool jacobians = d_u_d_pose != nullptr || d_u_d_landmark != nullptr;
  Eigen::Matrix<double, 2, 3> d_pixel_d_pose, d_pixel_d_point;
  const std::optional<Eigen::Vector2d> pixel = ProjectWorldPoint(
      world_from_robot, Eigen::Vector3d(plate_in_world.x(), plate_in_world.y(), plate_height_m),
      robot_from_camera, model, jacobians ? &d_pixel_d_pose : nullptr,
      jacobians ? &d_pixel_d_point : nullptr);
  if (!pixel) return std::nullopt;
  if (d_u_d_pose != nullptr) *d_u_d_pose = d_pixel_d_pose.row(0);
  if (d_u_d_landmark != nullptr) *d_u_d_landmark = d_pixel_d_point.block<1, 2>(0, 0);
  return pixel->x();
}

std::optional<Eigen::Vector2d> InitVanishingPoint(const SE2& world_from_robot, double u,
                                                  double virtual_distance_m,
                                                  const SE3& robot_from_camera,
                                                  const CameraModel& model,
                                                  Eigen::Matrix<double, 2, 3>* d_landmark_d_pose,
                                                  Eigen::Vector2d* d_landmark_d_u) {
  CheckOrDie(virtual_distance_m > 0.0 && std::isfinite(virtual_distance_m), "InitVanishingPoint",
             "virtual distance must be positive and finite");
  const std::optional<ColumnPlane> plane = ColumnPlaneOf(u, robot_from_camera, model);
  if (!plane) return std::nullopt;
  // The plane meets the horizontal plane through the camera centre in a line through the centre,
  // direction Perp(n_xy); take the half in front of the camera.
  const Eigen::Vector2d normal_xy = plane->normal_in_robot.head<2>();
  const double length = normal_xy.norm();
  if (!(length > 1e-9)) return std::nullopt;  // the column's plane is horizontal
  const Eigen::Vector2d forward_xy = robot_from_camera.rotation().col(2).head<2>();
  Eigen::Vector2d direction = Perp(normal_xy) / length;
  const double ahead = direction.dot(forward_xy);
  if (std::abs(ahead) < 1e-9) return std::nullopt;  // the line is square to the optical axis
  const double sign = ahead > 0.0 ? 1.0 : -1.0;
  direction *= sign;
  const Eigen::Vector2d p_in_robot =
      robot_from_camera.translation().head<2>() + virtual_distance_m * direction;
  const Eigen::Matrix2d world_r_robot = world_from_robot.rotation();
  const Eigen::Vector2d offset_in_world = world_r_robot * p_in_robot;
  if (d_landmark_d_pose != nullptr) {
    d_landmark_d_pose->leftCols<2>().setIdentity();
    d_landmark_d_pose->col(2) = Perp(offset_in_world);
  }
  if (d_landmark_d_u != nullptr) {
    const Eigen::Vector2d d_perp = Perp(plane->d_normal_d_u.head<2>());
    const Eigen::Vector2d d_direction =
        sign * (Eigen::Matrix2d::Identity() - direction * direction.transpose()) * d_perp / length;
    *d_landmark_d_u = world_r_robot * (virtual_distance_m * d_direction);
  }
  return world_from_robot.translation() + offset_in_world;
}

std::optional<PlateTriangulation> TriangulateDoorPlate(
    const SE2& world_from_robot_first, double u_first, const SE2& world_from_robot_second,
    double u_second, double plate_height_m, const SE3& robot_from_camera, const CameraModel& model,
    Eigen::Matrix<double, 2, 3>* d_plate_d_pose_first, Eigen::Vector2d* d_plate_d_u_first,
    Eigen::Matrix<double, 2, 3>* d_plate_d_pose_second, Eigen::Vector2d* d_plate_d_u_second) {
  if (!std::isfinite(plate_height_m)) return std::nullopt;
  const SE2* poses[2] = {&world_from_robot_first, &world_from_robot_second};
  const double us[2] = {u_first, u_second};
  const Eigen::Vector3d& camera_in_robot = robot_from_camera.translation();
  // Sighting i: the column's plane n . (p_in_robot - c) = 0 at height h is the world line
  // g_i(p) = a_i . (p - t_i) + k_i = 0 with a_i = R_i n_xy, k_i = n_z h - n . c.
  ColumnPlane planes[2];
  Eigen::Vector2d a[2];
  Eigen::Matrix2d lines;
  Eigen::Vector2d rhs;
  for (int i = 0; i < 2; ++i) {
    const std::optional<ColumnPlane> plane = ColumnPlaneOf(us[i], robot_from_camera, model);
    if (!plane) return std::nullopt;
    planes[i] = *plane;
    const Eigen::Vector3d& n = plane->normal_in_robot;
    a[i] = poses[i]->rotation() * n.head<2>();
    const double k = n.z() * plate_height_m - n.dot(camera_in_robot);
    lines.row(i) = a[i].transpose();
    rhs[i] = a[i].dot(poses[i]->translation()) - k;
  }
  const double det = lines.determinant();
  if (!(std::abs(det) > 1e-9 * a[0].norm() * a[1].norm())) return std::nullopt;  // parallel
  const Eigen::Matrix2d inverse = lines.inverse();
  const Eigen::Vector2d plate = inverse * rhs;
  const Eigen::Vector3d plate_3d(plate.x(), plate.y(), plate_height_m);
  PlateTriangulation result{plate, 0.0};
  Eigen::Vector3d rays[2];
  for (int i = 0; i < 2; ++i) {
    if (!(WorldPointInCamera(*poses[i], plate_3d, robot_from_camera).z() > 0.0)) {
      return std::nullopt;
    }
    Eigen::Vector3d centre;
    centre.head<2>() = *poses[i] * Eigen::Vector2d(camera_in_robot.head<2>());
    centre.z() = camera_in_robot.z();
    rays[i] = plate_3d - centre;
  }
  result.parallax_rad = std::atan2(rays[0].cross(rays[1]).norm(), rays[0].dot(rays[1]));
  // Implicit differentiation of A p = c: dp/d theta_i = -A^-1 e_i d g_i / d theta_i.
  Eigen::Matrix<double, 2, 3>* d_pose[2] = {d_plate_d_pose_first, d_plate_d_pose_second};
  Eigen::Vector2d* d_u[2] = {d_plate_d_u_first, d_plate_d_u_second};
  for (int i = 0; i < 2; ++i) {
    const Eigen::Vector2d from_robot = plate - poses[i]->translation();
    const Eigen::Vector2d minus_column = -inverse.col(i);
    if (d_pose[i] != nullptr) {
      Eigen::RowVector3d d_g_d_pose;
      d_g_d_pose << -a[i].transpose(), Perp(a[i]).dot(from_robot);
      *d_pose[i] = minus_column * d_g_d_pose;
    }
    if (d_u[i] != nullptr) {
      const Eigen::Vector3d& dn = planes[i].d_normal_d_u;
      const double d_g_d_u = (poses[i]->rotation() * dn.head<2>()).dot(from_robot) +
                             dn.z() * plate_height_m - dn.dot(camera_in_robot);
      *d_u[i] = minus_column * d_g_d_u;
    }
  }
  return result;
}

std::optional<Eigen::Vector3d> UnprojectRgbdPoint(const SE2& world_from_robot,
                                                  const Eigen::Vector3d& pixel_and_depth,
                                                  const SE3& robot_from_camera,
                                                  const CameraModel& model,
                                                  Eigen::Matrix3d* d_point_d_pose,
                                                  Eigen::Matrix3d* d_point_d_measurement) {
  if (!pixel_and_depth.allFinite()) return std::nullopt;
  const double depth = pixel_and_depth.z();
  if (!(depth > 0.0)) return std::nullopt;
  Eigen::Matrix<double, 3, 2> d_bearing_d_pixel;
  const Eigen::Vector3d bearing = model.Unproject(pixel_and_depth.head<2>(), &d_bearing_d_pixel);
  if (!(bearing.z() > 1e-9)) return std::nullopt;
  // p_in_camera = depth * q with q = bearing / bearing_z (q_z = 1: depth is z in the camera).
  const Eigen::Vector3d q = bearing / bearing.z();
  const Eigen::Vector3d p_in_camera = depth * q;
  const Eigen::Matrix3d robot_r_camera = robot_from_camera.rotation();
  const Eigen::Vector3d p_in_robot = robot_r_camera * p_in_camera + robot_from_camera.translation();
  const Eigen::Matrix2d world_r_robot = world_from_robot.rotation();
  const Eigen::Vector2d offset_in_world = world_r_robot * p_in_robot.head<2>();
  if (d_point_d_pose != nullptr) {
    d_point_d_pose->setZero();
    d_point_d_pose->topLeftCorner<2, 2>().setIdentity();
    d_point_d_pose->block<2, 1>(0, 2) = Perp(offset_in_world);
  }
  if (d_point_d_measurement != nullptr) {
    Eigen::Matrix3d d_camera_d_measurement;
    d_camera_d_measurement.leftCols<2>() =
        depth * (d_bearing_d_pixel * bearing.z() - bearing * d_bearing_d_pixel.row(2)) /
        (bearing.z() * bearing.z());
    d_camera_d_measurement.col(2) = q;
    Eigen::Matrix3d world_r_robot_3d = Eigen::Matrix3d::Identity();
    world_r_robot_3d.topLeftCorner<2, 2>() = world_r_robot;
    *d_point_d_measurement = world_r_robot_3d * robot_r_camera * d_camera_d_measurement;
  }
  Eigen::Vector3d p_in_world;
  p_in_world.head<2>() = world_from_robot.translation() + offset_in_world;
  p_in_world.z() = p_in_robot.z();
  return p_in_world;
}

Eigen::Vector2d RangeBearing(const SE2& world_from_robot, const Eigen::Vector2d& landmark_in_world,
                             Eigen::Matrix<double, 2, 3>* d_z_d_pose,
                             Eigen::Matrix2d* d_z_d_landmark) {
  const Eigen::Vector2d delta = landmark_in_world - world_from_robot.translation();
  const double range_sq = delta.squaredNorm();
  const double range = std::sqrt(range_sq);
  CheckOrDie(range > 0.0, "RangeBearing", "landmark on the robot");
  const double bearing = NormalizeAngle(std::atan2(delta.y(), delta.x()) - world_from_robot.yaw());
  Eigen::Matrix2d d_z_d_delta;
  d_z_d_delta.row(0) = delta.transpose() / range;
  d_z_d_delta.row(1) = Perp(delta).transpose() / range_sq;
  if (d_z_d_pose != nullptr) {
    d_z_d_pose->leftCols<2>() = -d_z_d_delta;
    d_z_d_pose->col(2) = Eigen::Vector2d(0.0, -1.0);
  }
  if (d_z_d_landmark != nullptr) *d_z_d_landmark = d_z_d_delta;
  return Eigen::Vector2d(range, bearing);
}

Eigen::Vector2d RangeBearingInverse(const SE2& world_from_robot,
                                    const Eigen::Vector2d& range_bearing,
                                    Eigen::Matrix<double, 2, 3>* d_landmark_d_pose,
                                    Eigen::Matrix2d* d_landmark_d_z) {
  const double angle = world_from_robot.yaw() + range_bearing.y();
  const Eigen::Vector2d unit(std::cos(angle), std::sin(angle));
  const Eigen::Vector2d offset = range_bearing.x() * unit;
  if (d_landmark_d_pose != nullptr) {
    d_landmark_d_pose->leftCols<2>().setIdentity();
    d_landmark_d_pose->col(2) = Perp(offset);
  }
  if (d_landmark_d_z != nullptr) {
    d_landmark_d_z->col(0) = unit;
    d_landmark_d_z->col(1) = Perp(offset);
  }
  return world_from_robot.translation() + offset;
}

}  // namespace corridorsim::slam::ekf
