// Rendered lateral-camera views of door plates, walls and posters for the detector tests: a
// generated default world, a level lateral camera (640x480, 60 deg, mast at (0, 0.12, 1.5) m,
// yaw 90 deg, noise on), placed at a distance in front of a target on a wall.
#pragma once

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "tests/support/uploaded_rig.h"
#include "worlds/world.h"

namespace corridorsim::test {

inline render::RigOptions LevelLateralRig() {
  render::RigOptions rig = render::RigOptions::Default();
  std::vector<render::CameraOptions> cameras;
  for (const render::CameraOptions& c : rig.cameras) {
    if (c.id != "lateral") continue;
    render::CameraOptions lateral = c;
    lateral.enabled = true;
    lateral.mount = render::Mount{0.0, 0.12, 1.5, 90.0, 0.0, 0.0};
    cameras.push_back(lateral);
  }
  rig.cameras = cameras;
  return rig;
}

struct LateralView {
  render::CameraFrame frame;
  render::FrameTruth truth;
};

/// The lateral camera `distance_m` in front of `target` (on a wall with unit `normal` into the
/// corridor), looking straight at it.
inline LateralView ViewTarget(const worlds::World& world, UploadedRig& rig,
                              const Eigen::Vector3d& target, const Eigen::Vector3d& normal,
                              double distance_m) {
  const render::CameraOptions& lateral = rig.rig().cameras().front().options();
  const Eigen::Vector2d n = normal.head<2>().normalized();
  const Eigen::Vector2d camera = target.head<2>() + distance_m * n;
  const double camera_yaw = std::atan2(-n.y(), -n.x());
  const double robot_yaw = camera_yaw - lateral.mount.yaw_deg * std::numbers::pi / 180.0;
  const Eigen::Vector2d robot = camera - Eigen::Rotation2Dd(robot_yaw) *
                                             Eigen::Vector2d(lateral.mount.x_m, lateral.mount.y_m);
  const SE3 world_from_robot = SE3::FromSE2(SE2(robot.x(), robot.y(), robot_yaw));
  LateralView view;
  rig.rig().RenderCamera(0, world_from_robot, 7, 0, &view.frame);
  render::FrameTruthInput input;
  input.world = &world;
  input.camera_id = view.frame.camera_id;
  input.model = lateral.model;
  input.world_from_camera = view.frame.world_from_camera;
  input.world_from_robot = world_from_robot;
  input.instance = &view.frame.instance;
  input.semantic = &view.frame.semantic;
  view.truth = render::ComputeFrameTruth(input);
  return view;
}

}  // namespace corridorsim::test
