// Rigid transforms in 2D and 3D. Naming follows `a_from_b`: `world_from_robot * p_in_robot` gives
// p_in_world, and `a_from_b * b_from_c` gives a_from_c.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace corridorsim {

// Wraps an angle to (-pi, pi] (rad).
double NormalizeAngle(double rad);

// Planar rigid transform: a rotation by yaw (rad, counter-clockwise, kept in (-pi, pi]) followed by
// a translation (m).
class SE2 {
 public:
  SE2() = default;
  SE2(double x, double y, double yaw);
  SE2(const Eigen::Vector2d& translation, double yaw);

  static SE2 Identity() { return SE2(); }

  double x() const { return translation_.x(); }
  double y() const { return translation_.y(); }
  double yaw() const { return yaw_; }
  const Eigen::Vector2d& translation() const { return translation_; }
  Eigen::Matrix2d rotation() const;

  // a_from_b * b_from_c = a_from_c.
  SE2 operator*(const SE2& other) const;
  // a_from_b * p_in_b = p_in_a.
  Eigen::Vector2d operator*(const Eigen::Vector2d& p) const;
  SE2 Inverse() const;

  // Plain parameters (x m, y m, yaw rad), NOT the se(2) tangent vector: translation is not rotated
  // back through the left Jacobian.
  Eigen::Vector3d Log() const;

  // Component-wise interpolation: translation linear in t, yaw along the shorter arc from a.yaw()
  // to b.yaw(). This is not the SE(2) geodesic (which would bend the translation path); it matches
  // SE3::Interpolate (slerp + linear translation). t = 0 gives a, t = 1 gives b.
  static SE2 Interpolate(const SE2& a, const SE2& b, double t);

  // Homogeneous 3x3 matrix [R t; 0 0 1].
  Eigen::Matrix3d ToMatrix() const;

 private:
  Eigen::Vector2d translation_ = Eigen::Vector2d::Zero();  // m
  double yaw_ = 0.0;                                       // rad, in (-pi, pi]
};

// Spatial rigid transform: a unit quaternion (kept normalised) followed by a translation (m).
class SE3 {
 public:
  SE3() = default;
  // `quaternion` is normalised here; it must be non-zero.
  SE3(const Eigen::Quaterniond& quaternion, const Eigen::Vector3d& translation);
  // `rotation` must be a rotation matrix (orthonormal, det +1).
  SE3(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation);
  /// A pose read back exactly (a recording, docs/recordings.md): `unit` was normalized when the
  /// pose was made, so it is kept as it is, bit for bit (normalizing again may move the last bit).
  static SE3 FromStored(const Eigen::Quaterniond& unit, const Eigen::Vector3d& translation);

  static SE3 Identity() { return SE3(); }
  // Planar pose lifted to 3D: yaw about +z, translation (x, y, z).
  static SE3 FromSE2(const SE2& pose, double z = 0.0);
  // R = Rz(yaw) * Ry(pitch) * Rx(roll): intrinsic Z-Y'-X'' rotations (rad), the aerospace
  // convention; equal to extrinsic X, then Y, then Z.
  static SE3 FromYawPitchRoll(double yaw, double pitch, double roll,
                              const Eigen::Vector3d& translation = Eigen::Vector3d::Zero());

  const Eigen::Quaterniond& quaternion() const { return quaternion_; }
  Eigen::Matrix3d rotation() const { return quaternion_.toRotationMatrix(); }
  const Eigen::Vector3d& translation() const { return translation_; }

  // a_from_b * b_from_c = a_from_c.
  SE3 operator*(const SE3& other) const;
  // a_from_b * p_in_b = p_in_a.
  Eigen::Vector3d operator*(const Eigen::Vector3d& p) const;
  SE3 Inverse() const;

  // Rotation by slerp along the shorter arc, translation linear in t. t = 0 gives a, t = 1 gives b.
  static SE3 Interpolate(const SE3& a, const SE3& b, double t);

  // Homogeneous 4x4 matrix [R t; 0 0 0 1].
  Eigen::Matrix4d ToMatrix() const;

 private:
  Eigen::Quaterniond quaternion_ = Eigen::Quaterniond::Identity();  // unit norm
  Eigen::Vector3d translation_ = Eigen::Vector3d::Zero();           // m
};

}  // namespace corridorsim
