#include "common/pose.h"

#include <cmath>
#include <numbers>

namespace corridorsim {

double NormalizeAngle(double rad) {
  // std::remainder gives [-pi, pi]; the closed end at -pi moves to +pi.
  const double wrapped = std::remainder(rad, 2.0 * std::numbers::pi);
  return wrapped <= -std::numbers::pi ? wrapped + 2.0 * std::numbers::pi : wrapped;
}

SE2::SE2(double x, double y, double yaw) : translation_(x, y), yaw_(NormalizeAngle(yaw)) {}

SE2::SE2(const Eigen::Vector2d& translation, double yaw)
    : translation_(translation), yaw_(NormalizeAngle(yaw)) {}

Eigen::Matrix2d SE2::rotation() const {
  const double c = std::cos(yaw_);
  const double s = std::sin(yaw_);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

SE2 SE2::operator*(const SE2& other) const {
  return SE2(rotation() * other.translation_ + translation_, yaw_ + other.yaw_);
}

Eigen::Vector2d SE2::operator*(const Eigen::Vector2d& p) const {
  return rotation() * p + translation_;
}

SE2 SE2::Inverse() const { return SE2(-(rotation().transpose() * translation_), -yaw_); }

Eigen::Vector3d SE2::Log() const { return Eigen::Vector3d(x(), y(), yaw_); }

SE2 SE2::Interpolate(const SE2& a, const SE2& b, double t) {
  const double yaw_step = NormalizeAngle(b.yaw_ - a.yaw_);
  return SE2(a.translation_ + t * (b.translation_ - a.translation_), a.yaw_ + t * yaw_step);
}

Eigen::Matrix3d SE2::ToMatrix() const {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  m.topLeftCorner<2, 2>() = rotation();
  m.topRightCorner<2, 1>() = translation_;
  return m;
}

SE3::SE3(const Eigen::Quaterniond& quaternion, const Eigen::Vector3d& translation)
    : quaternion_(quaternion.normalized()), translation_(translation) {}

SE3::SE3(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation)
    : quaternion_(Eigen::Quaterniond(rotation).normalized()), translation_(translation) {}

SE3 SE3::FromStored(const Eigen::Quaterniond& unit, const Eigen::Vector3d& translation) {
  SE3 pose;
  pose.quaternion_ = unit;
  pose.translation_ = translation;
  return pose;
}

SE3 SE3::FromSE2(const SE2& pose, double z) {
  return SE3(Eigen::Quaterniond(Eigen::AngleAxisd(pose.yaw(), Eigen::Vector3d::UnitZ())),
             Eigen::Vector3d(pose.x(), pose.y(), z));
}

SE3 SE3::FromYawPitchRoll(double yaw, double pitch, double roll,
                          const Eigen::Vector3d& translation) {
  const Eigen::Quaterniond q = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
  return SE3(q, translation);
}

SE3 SE3::operator*(const SE3& other) const {
  return SE3(quaternion_ * other.quaternion_, quaternion_ * other.translation_ + translation_);
}

Eigen::Vector3d SE3::operator*(const Eigen::Vector3d& p) const {
  return quaternion_ * p + translation_;
}

SE3 SE3::Inverse() const {
  const Eigen::Quaterniond inverse_rotation = quaternion_.conjugate();
  return SE3(inverse_rotation, -(inverse_rotation * translation_));
}

SE3 SE3::Interpolate(const SE3& a, const SE3& b, double t) {
  return SE3(a.quaternion_.slerp(t, b.quaternion_),
             a.translation_ + t * (b.translation_ - a.translation_));
}

Eigen::Matrix4d SE3::ToMatrix() const {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = rotation();
  m.topRightCorner<3, 1>() = translation_;
  return m;
}

}  // namespace corridorsim
