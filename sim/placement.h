#pragma once
// Physical sanity of a scenario against its world, checked before anything runs: the robot's
// chassis (ChassisBoxes) swept along the WHOLE planned path, turns and turnarounds included, must
// stay clear of the world's solids (walls, closed door leaves, door frames, furniture:
// worlds::World::collision_boxes), and every checked camera's optical centre must stay farther
// than render::kCameraClearanceM (its views' near plane and 1 cm) from them and inside the
// corridor or a room, that far from its walls, floor and ceiling: a camera closer to a surface
// than its near plane sees through it (a camera 1 m ahead of the axle at a corridor's end wall
// rendered black frames). Doorways the path passes are no obstacle; closed doors are.
//
// The path is swept as the robot is asked to drive it: straight legs exactly (the footprint's
// convex hull at both ends of a leg is the area a translating box covers), in-place turns and a
// script's arcs in steps short enough that no point of the robot or a camera leaves the chord
// between two steps by more than kMaxSagittaM. The check is deterministic and costs a few
// milliseconds for the shipped scenarios (a grid over the world's boxes keeps it linear).

#include <optional>
#include <string>

#include "common/error.h"
#include "render/camera_rig.h"
#include "sim/laser_scanner.h"
#include "sim/robot.h"
#include "sim/robot_path.h"
#include "worlds/world.h"

namespace corridorsim::sim {

/// The most (m) any swept point may leave the chord between two steps of a turn or an arc.
inline constexpr double kMaxSagittaM = 1e-4;

/// A placement problem and the scenario section its key belongs to.
struct PlacementProblem {
  std::string section;     // "robot" (body_*), "sensors" (<camera>.mount) or "path"
  OptionsProblem problem;  // key relative to `section`
};

/// The first problem along `path` (in driving order): the robot's chassis intersecting a solid,
/// or an enabled camera of `rig` (null: cameras are not checked) inside a solid, outside the
/// corridor and rooms, or above the ceiling. A chassis problem names the body dimension that
/// makes it (body_width_m, body_length_m, body_height_m, wheelbase_m: the first whose default
/// would fit), else the path (`commands` of a script, otherwise `kind`); a camera problem names
/// `<camera>.mount`.
/// `lasers`: the scenario's scanners; an enabled one's origin must lie outside the chassis and
/// keep a camera's clearance along the path (a problem names `<scanner>.mount`).
std::optional<PlacementProblem> CheckPathPlacement(const worlds::World& world,
                                                   const RobotOptions& robot, const RobotPath& path,
                                                   const render::RigOptions* rig,
                                                   const std::vector<LaserOptions>& lasers = {});

}  // namespace corridorsim::sim
