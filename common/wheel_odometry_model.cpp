#include "common/wheel_odometry_model.h"

#include <cassert>
#include <cmath>

namespace corridorsim {

SE2 ApplyWheelOdometry(const SE2& pose, double left_m, double right_m, double wheelbase_m,
                       Eigen::Matrix3d* d_pose_d_pose, Eigen::Matrix<double, 3, 2>* d_pose_d_lr) {
  assert(wheelbase_m > 0.0);
  // P1 eq. 13: mean travel along the midpoint heading, turn by the wheels' difference over B.
  const double travel_m = 0.5 * (right_m + left_m);
  const double turn_rad = (right_m - left_m) / wheelbase_m;
  const double heading_rad = pose.yaw() + 0.5 * turn_rad;
  const double c = std::cos(heading_rad);
  const double s = std::sin(heading_rad);

  // F = d f / d x_r (P1 eqs. 14-15).
  if (d_pose_d_pose != nullptr) {
    *d_pose_d_pose << 1.0, 0.0, -travel_m * s,  //
        0.0, 1.0, travel_m * c,                 //
        0.0, 0.0, 1.0;
  }
  // G = d f / d u with u = (s_l, s_r) (P1 eqs. 14, 16): d travel / d s_{l,r} = 1/2 and
  // d heading / d s_{l,r} = -+1 / (2 B).
  if (d_pose_d_lr != nullptr) {
    const double half_turn_lever = travel_m / (2.0 * wheelbase_m);
    *d_pose_d_lr << 0.5 * c + half_turn_lever * s, 0.5 * c - half_turn_lever * s,  //
        0.5 * s - half_turn_lever * c, 0.5 * s + half_turn_lever * c,              //
        -1.0 / wheelbase_m, 1.0 / wheelbase_m;
  }
  return SE2(pose.x() + travel_m * c, pose.y() + travel_m * s, pose.yaw() + turn_rad);
}

Eigen::Matrix2d WheelOdometryNoise(double left_m, double right_m, double k) {
  assert(k >= 0.0);
  // P1 eq. 17, reordered to (s_l, s_r).
  Eigen::Matrix2d q = Eigen::Matrix2d::Zero();
  q(0, 0) = k * std::abs(left_m);
  q(1, 1) = k * std::abs(right_m);
  return q;
}

}  // namespace corridorsim
