#include "slam/ekf/upward_models.h"

#include <cmath>

namespace corridorsim::slam::ekf {
namespace {

// Rz(yaw) and its derivative.
Eigen::Matrix3d Rz(double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  Eigen::Matrix3d r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  return r;
}
Eigen::Matrix3d DRz(double yaw) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  Eigen::Matrix3d r;
  r << -s, -c, 0, c, -s, 0, 0, 0, 0;
  return r;
}

// The camera centre's (x, y) in the world and its Jacobian over (x, y, yaw).
Eigen::Vector2d CameraCentre(const SE2& pose, const SE3& robot_from_camera,
                             Eigen::Matrix<double, 2, 3>* d_centre_d_pose) {
  const Eigen::Vector3d t = robot_from_camera.translation();
  const double c = std::cos(pose.yaw()), s = std::sin(pose.yaw());
  if (d_centre_d_pose) {
    *d_centre_d_pose << 1, 0, -s * t.x() - c * t.y(), 0, 1, c * t.x() - s * t.y();
  }
  return {pose.x() + c * t.x() - s * t.y(), pose.y() + s * t.x() + c * t.y()};
}

}  // namespace

double CameraHeight(const SE3& robot_from_camera) { return robot_from_camera.translation().z(); }

Eigen::Vector3d InverseDepthToPoint(const InverseDepthPoint& l, double camera_height_m,
                                    Eigen::Matrix<double, 3, 5>* d_point_d_landmark) {
  const double inv = 1.0 / l(4);
  if (d_point_d_landmark) {
    *d_point_d_landmark << 1, 0, inv, 0, -l(2) * inv * inv,  //
        0, 1, 0, inv, -l(3) * inv * inv,                     //
        0, 0, 0, 0, -inv * inv;
  }
  return {l(0) + l(2) * inv, l(1) + l(3) * inv, camera_height_m + inv};
}

Eigen::Vector2d PixelToPolar(const Eigen::Vector2d& pixel, const CameraModel& model,
                             Eigen::Matrix2d* d_polar_d_pixel) {
  const Eigen::Vector2d d = pixel - model.principal_point();
  const double du = d.x(), dv = d.y();
  const double r2 = du * du + dv * dv, r = std::sqrt(r2);
  if (d_polar_d_pixel) *d_polar_d_pixel << du / r, dv / r, -dv / r2, du / r2;
  return {r, std::atan2(dv, du)};
}

std::optional<Eigen::Vector2d> InverseDepthPixel(const SE2& pose, const InverseDepthPoint& l,
                                                 const SE3& robot_from_camera,
                                                 const CameraModel& model,
                                                 Eigen::Matrix<double, 2, 3>* d_pixel_d_pose,
                                                 Eigen::Matrix<double, 2, 5>* d_pixel_d_landmark) {
  if (!(l(4) > 0.0)) return std::nullopt;
  Eigen::Matrix<double, 2, 3> d_c;
  const Eigen::Vector2d c = CameraCentre(pose, robot_from_camera, &d_c);
  const double rho = l(4);
  // g = (rho (x0 - xc) + mx, rho (y0 - yc) + my, 1) in the world; p_cam = R_cw g.
  const Eigen::Vector3d g(rho * (l(0) - c.x()) + l(2), rho * (l(1) - c.y()) + l(3), 1.0);
  const Eigen::Matrix3d r_rc = robot_from_camera.rotation();
  const Eigen::Matrix3d r_cw = r_rc.transpose() * Rz(pose.yaw()).transpose();
  const Eigen::Vector3d p = r_cw * g;
  Eigen::Matrix<double, 2, 3> d_pixel_d_p;
  const std::optional<Eigen::Vector2d> pixel = model.Project(p, &d_pixel_d_p);
  if (!pixel) return std::nullopt;
  if (d_pixel_d_pose || d_pixel_d_landmark) {
    // d p / d g = R_cw; d g / d c_xy = -rho I (rows x, y); d R_cw / d yaw = R_rc^T DRz^T.
    Eigen::Matrix<double, 3, 2> d_g_d_c = Eigen::Matrix<double, 3, 2>::Zero();
    d_g_d_c(0, 0) = -rho;
    d_g_d_c(1, 1) = -rho;
    if (d_pixel_d_pose) {
      Eigen::Matrix<double, 3, 3> d_p_d_pose = r_cw * d_g_d_c * d_c;
      d_p_d_pose.col(2) += r_rc.transpose() * DRz(pose.yaw()).transpose() * g;
      *d_pixel_d_pose = d_pixel_d_p * d_p_d_pose;
    }
    if (d_pixel_d_landmark) {
      Eigen::Matrix<double, 3, 5> d_g_d_l = Eigen::Matrix<double, 3, 5>::Zero();
      d_g_d_l(0, 0) = rho;
      d_g_d_l(0, 2) = 1.0;
      d_g_d_l(0, 4) = l(0) - c.x();
      d_g_d_l(1, 1) = rho;
      d_g_d_l(1, 3) = 1.0;
      d_g_d_l(1, 4) = l(1) - c.y();
      *d_pixel_d_landmark = d_pixel_d_p * r_cw * d_g_d_l;
    }
  }
  return pixel;
}

std::optional<Eigen::Vector2d> InverseDepthPolar(const SE2& pose, const InverseDepthPoint& l,
                                                 const SE3& robot_from_camera,
                                                 const CameraModel& model,
                                                 Eigen::Matrix<double, 2, 3>* d_polar_d_pose,
                                                 Eigen::Matrix<double, 2, 5>* d_polar_d_landmark) {
  Eigen::Matrix<double, 2, 3> d_pose;
  Eigen::Matrix<double, 2, 5> d_landmark;
  const std::optional<Eigen::Vector2d> pixel =
      InverseDepthPixel(pose, l, robot_from_camera, model, d_polar_d_pose ? &d_pose : nullptr,
                        d_polar_d_landmark ? &d_landmark : nullptr);
  if (!pixel) return std::nullopt;
  if (!((*pixel - model.principal_point()).norm() > 0.0)) return std::nullopt;
  Eigen::Matrix2d d_polar_d_pixel;
  const Eigen::Vector2d polar = PixelToPolar(*pixel, model, &d_polar_d_pixel);
  if (d_polar_d_pose) *d_polar_d_pose = d_polar_d_pixel * d_pose;
  if (d_polar_d_landmark) *d_polar_d_landmark = d_polar_d_pixel * d_landmark;
  return polar;
}

std::optional<InverseDepthPoint> InitInverseDepthPoint(
    const SE2& pose, const Eigen::Vector2d& pixel, double rho, const SE3& robot_from_camera,
    const CameraModel& model, double min_ray_z, Eigen::Matrix<double, 5, 3>* d_landmark_d_pose,
    Eigen::Matrix<double, 5, 3>* d_landmark_d_measurement) {
  if (!model.IsInImage(pixel)) return std::nullopt;
  Eigen::Matrix<double, 3, 2> d_bearing_d_pixel;
  const Eigen::Vector3d bearing = model.Unproject(pixel, &d_bearing_d_pixel);
  const Eigen::Matrix3d r_rc = robot_from_camera.rotation();
  const Eigen::Matrix3d r_wc = Rz(pose.yaw()) * r_rc;
  const Eigen::Vector3d ray = r_wc * bearing;  // unit, in the world
  if (!(ray.z() >= min_ray_z) || !(ray.z() > 0.0)) return std::nullopt;
  Eigen::Matrix<double, 2, 3> d_c;
  const Eigen::Vector2d c = CameraCentre(pose, robot_from_camera, &d_c);
  InverseDepthPoint l;
  l << c.x(), c.y(), ray.x() / ray.z(), ray.y() / ray.z(), rho;
  // d m / d ray: m = (rx / rz, ry / rz).
  Eigen::Matrix<double, 2, 3> d_m_d_ray;
  d_m_d_ray << 1 / ray.z(), 0, -ray.x() / (ray.z() * ray.z()), 0, 1 / ray.z(),
      -ray.y() / (ray.z() * ray.z());
  if (d_landmark_d_pose) {
    d_landmark_d_pose->setZero();
    d_landmark_d_pose->topRows<2>() = d_c;
    d_landmark_d_pose->block<2, 1>(2, 2) = d_m_d_ray * (DRz(pose.yaw()) * r_rc * bearing);
  }
  if (d_landmark_d_measurement) {
    d_landmark_d_measurement->setZero();
    d_landmark_d_measurement->block<2, 2>(2, 0) = d_m_d_ray * r_wc * d_bearing_d_pixel;
    (*d_landmark_d_measurement)(4, 2) = 1.0;
  }
  return l;
}

Eigen::Vector2d CameraXY(const SE2& pose, const Eigen::Vector2d& camera_xy,
                         Eigen::Matrix<double, 2, 3>* d_xy_d_pose) {
  const double c = std::cos(pose.yaw()), s = std::sin(pose.yaw());
  const Eigen::Vector2d turned(c * camera_xy.x() - s * camera_xy.y(),
                               s * camera_xy.x() + c * camera_xy.y());
  if (d_xy_d_pose) {
    *d_xy_d_pose << 1.0, 0.0, -turned.y(), 0.0, 1.0, turned.x();
  }
  return Eigen::Vector2d(pose.x(), pose.y()) + turned;
}

std::optional<Eigen::Vector2d> DoorBearings(const SE2& pose, const DoorColumns& door,
                                            const Eigen::Vector2d& camera_xy,
                                            Eigen::Matrix<double, 2, 3>* d_pose,
                                            Eigen::Matrix<double, 2, 4>* d_door) {
  Eigen::Matrix<double, 2, 3> d_c;
  const Eigen::Vector2d c = CameraXY(pose, camera_xy, &d_c);
  Eigen::Vector2d out;
  if (d_pose) d_pose->setZero();
  if (d_door) d_door->setZero();
  for (int i = 0; i < 2; ++i) {
    const double dx = door(2 * i) - c.x(), dy = door(2 * i + 1) - c.y();
    const double q = dx * dx + dy * dy;
    if (!(q > 1e-12)) return std::nullopt;
    // P3 eq. 17.
    out(i) = NormalizeAngle(std::atan2(dy, dx) - pose.yaw());
    const Eigen::RowVector2d d_c_row(dy / q, -dx / q);  // d theta / d C
    if (d_pose) {
      d_pose->row(i) = d_c_row * d_c;
      (*d_pose)(i, 2) -= 1.0;
    }
    if (d_door) {
      (*d_door)(i, 2 * i) = -dy / q;
      (*d_door)(i, 2 * i + 1) = dx / q;
    }
  }
  return out;
}

DoorColumns DoorFromBearings(const SE2& pose, const Eigen::Vector4d& z,
                             const Eigen::Vector2d& camera_xy, Eigen::Matrix<double, 4, 3>* d_pose,
                             Eigen::Matrix<double, 4, 4>* d_measurement) {
  Eigen::Matrix<double, 2, 3> d_c;
  const Eigen::Vector2d c = CameraXY(pose, camera_xy, &d_c);
  DoorColumns door;
  if (d_pose) d_pose->setZero();
  if (d_measurement) d_measurement->setZero();
  for (int i = 0; i < 2; ++i) {
    const double angle = pose.yaw() + z(i), range = z(2 + i);
    const Eigen::Vector2d u(std::cos(angle), std::sin(angle));
    door.segment<2>(2 * i) = c + range * u;
    const Eigen::Vector2d du(-u.y(), u.x());  // d u / d angle
    if (d_pose) {
      d_pose->block<2, 3>(2 * i, 0) = d_c;
      d_pose->block<2, 1>(2 * i, 2) += range * du;
    }
    if (d_measurement) {
      d_measurement->block<2, 1>(2 * i, i) = range * du;
      d_measurement->block<2, 1>(2 * i, 2 + i) = u;
    }
  }
  return door;
}

}  // namespace corridorsim::slam::ekf
