#pragma once
// The differential-drive motion model of P1 (eqs. 13-17): the robot pose after the wheels
// travelled (s_l, s_r), with its Jacobians F and G and the process noise Q. A pure function
// (STYLE item 5), shared by the simulator's tests and the SLAM prediction step.

#include <Eigen/Core>

#include "common/pose.h"

namespace corridorsim {

/// P1 eq. 13: the pose `world_from_robot` after the left and right wheels travelled `left_m` and
/// `right_m` (signed, m; positive = forward) on wheels `wheelbase_m` apart (B in P1). The robot
/// moves (s_l + s_r) / 2 along the midpoint heading phi + (s_r - s_l) / (2 B) and turns by
/// (s_r - s_l) / B; the returned yaw is wrapped into (-pi, pi].
///
/// Jacobians (optional, as P1 eqs. 14-16 use them), over the plain parameters (x m, y m, yaw rad):
///   `d_pose_d_pose` = F = d f / d x_r (3x3), columns (x, y, yaw) of the input pose;
///   `d_pose_d_lr`   = G = d f / d u   (3x2), columns (s_l, s_r) in that order: u = (s_l, s_r)
///                     as P1 writes it, whereas P1 eq. 17 lists Q with s_r first. Use
///                     WheelOdometryNoise below, which is in the same (s_l, s_r) order.
/// The yaw derivatives ignore the wrap into (-pi, pi] (they are those of the unwrapped angle).
SE2 ApplyWheelOdometry(const SE2& pose, double left_m, double right_m, double wheelbase_m,
                       Eigen::Matrix3d* d_pose_d_pose = nullptr,
                       Eigen::Matrix<double, 3, 2>* d_pose_d_lr = nullptr);

/// P1 eq. 17: the covariance of the wheel distances (m^2), diag(k |s_l|, k |s_r|), in the
/// (s_l, s_r) order of the columns of G above (P1 writes the s_r entry first). `k` (m^2 per m of
/// travel) must not be negative.
Eigen::Matrix2d WheelOdometryNoise(double left_m, double right_m, double k);

/// The default k of P1 eq. 17 (m^2 per m): 1 cm standard deviation per metre of wheel travel, P1's
/// used Pioneer. One value for both sides, so that a scenario that sets neither gets a simulated
/// robot (`robot.odometry.random_k_m`) and a filter (`pipelines.odometry.k_m`) that agree.
inline constexpr double kDefaultWheelNoiseK_m = 1e-4;

/// The most encoder counts per wheel revolution a robot may have (`robot.odometry.
/// ticks_per_revolution` and slam::Calibration check it): 1,000,000, a tick of 0.6 um of travel
/// on the Pioneer 3-DX's 195 mm wheel, 25 times the Pioneer's 39,400 counts. A finer tick measures
/// nothing a wheel does (its tyre deforms by more, and a real encoder's line count behind a
/// gearhead stays far below), and it keeps tick counts of any run far inside int64.
inline constexpr int kMaxTicksPerRevolution = 1'000'000;

}  // namespace corridorsim
