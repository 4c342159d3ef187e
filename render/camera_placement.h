#pragma once
// Where a camera may sit: its optical centre inside the corridor or a room and clear of every
// solid, wall, floor and ceiling by its near plane and 1 cm, or it sees through them. One pose
// here; sim::CheckPathPlacement sweeps the same rules along a whole path.

#include <optional>
#include <string>

#include <Eigen/Core>

#include "common/error.h"
#include "common/pose.h"
#include "render/camera_options.h"
#include "render/scene.h"
#include "worlds/world.h"

namespace corridorsim::render {

/// How far (m) a camera's optical centre must stay from every solid and from the boundary of the
/// corridor and the rooms (walls, floor, ceiling): the near plane of its views (kNearPlaneM),
/// within which a surface is clipped and the camera sees through it, plus 1 cm for the path
/// follower's tracking (it arrives within 2 mm of a waypoint, sim/robot_path.h).
inline constexpr double kCameraClearanceM = kNearPlaneM + 0.01;

/// Why a camera whose optical centre is at `p_in_world` would see through the world's boundary:
/// outside the corridor and the rooms ("outside the corridor (in or behind a wall)", "above the
/// ceiling (... m high)", "below the floor") or within kCameraClearanceM of a wall, the floor or a
/// ceiling; nullopt when clear. Solids (boxes) are not looked at (see CheckCameraPlacement).
std::optional<std::string> CameraSpaceProblem(const worlds::World& world,
                                              const Eigen::Vector3d& p_in_world);

/// A problem when a camera at `world_from_robot` would sit inside a solid or closer to one than
/// kCameraClearanceM, or where CameraSpaceProblem finds one (key "<camera>.mount"). One pose:
/// sim::CheckPathPlacement sweeps the same rules along a whole path.
std::optional<OptionsProblem> CheckCameraPlacement(const worlds::World& world,
                                                   const RigOptions& rig,
                                                   const SE3& world_from_robot);

}  // namespace corridorsim::render
