// A robot's planar step as the EKF tests and bench/bench_ekf.cpp simulate and predict it: the pose
// after a motion given in the robot frame, with the Jacobians of the prediction.
#pragma once

#include <Eigen/Core>

#include "common/pose.h"

namespace corridorsim::test {

/// `pose` moved by `delta_in_robot` (x ahead, y left, then the turn in rad), with the Jacobians
/// of the result by the pose (`f`) and by the motion (`g`) where asked for.
inline SE2 Compose(const SE2& pose, const Eigen::Vector3d& delta_in_robot,
                   Eigen::Matrix3d* f = nullptr, Eigen::Matrix3d* g = nullptr) {
  const Eigen::Vector2d step = pose.rotation() * delta_in_robot.head<2>();
  if (f != nullptr) {
    *f = Eigen::Matrix3d::Identity();
    f->block<2, 1>(0, 2) = Eigen::Vector2d(-step.y(), step.x());
  }
  if (g != nullptr) {
    *g = Eigen::Matrix3d::Identity();
    g->topLeftCorner<2, 2>() = pose.rotation();
  }
  return SE2(pose.translation() + step, pose.yaw() + delta_in_robot.z());
}

}  // namespace corridorsim::test
