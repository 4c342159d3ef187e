// Tests sim/placement.cpp: the robot's chassis and its cameras swept along the whole planned path
// against the world. The Pioneer and the default rig fit every path kind; a body too wide or too
// long, a camera above the ceiling, and a camera that only meets a wall during a turn are each
// refused with the key that causes them; the swept boxes are the ones Bullet collides.
#include "sim/placement.h"

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <tuple>

#include <catch2/catch.hpp>

#include "render/camera_placement.h"
#include "render/camera_rig.h"
#include "sim/robot.h"
#include "sim/robot_path.h"
#include "tests/support/generated_worlds.h"
#include "worlds/world.h"

namespace corridorsim::sim {
namespace {

// A straight corridor `length_m` long, `width_m` wide (walls at y = +-width_m / 2), 2.7 m high.
worlds::World Corridor(double length_m, int doors = 0, double width_m = 2.4) {
  worlds::WorldOptions world_options = test::BareCorridorOptions(length_m);
  world_options.width_m = width_m;
  world_options.doors.count = doors;
  return worlds::Generate(world_options, 5);
}

// The robot standing still at `pose` (a path with no legs).
RobotPath StandAt(const SE2& pose) {
  RobotPath path;
  path.world_from_start = pose;
  return path;
}

render::RigOptions WithMount(const std::string& camera, const render::Mount& mount) {
  render::RigOptions rig = render::RigOptions::Default();
  for (render::CameraOptions& c : rig.cameras) {
    if (c.id == camera) c.mount = mount;
  }
  return rig;
}

// Requires a placement problem in `section` at `key` whose message matches `message`.
template <class Matcher>
void CheckRefusedAt(const std::optional<PlacementProblem>& problem, const std::string& section,
                    const std::string& key, const Matcher& message) {
  REQUIRE(problem);
  CHECK(problem->section == section);
  CHECK(problem->problem.key == key);
  CHECK_THAT(problem->problem.message, message);
}

TEST_CASE("the Pioneer and the default rig fit every shipped path kind", "[sim][placement]") {
  const render::RigOptions rig = render::RigOptions::Default();
  for (const worlds::Layout layout : {worlds::Layout::kStraight, worlds::Layout::kLTurn,
                                      worlds::Layout::kTJunction, worlds::Layout::kLoop}) {
    worlds::WorldOptions world_options;
    world_options.layout = layout;
    const worlds::World world = worlds::Generate(world_options, 3);
    for (const PathKind kind :
         {PathKind::kRoundTrip, PathKind::kLoop, PathKind::kUmbmarkCw, PathKind::kUmbmarkCcw}) {
      if ((kind == PathKind::kLoop) != (layout == worlds::Layout::kLoop)) continue;
      CAPTURE(worlds::LayoutName(layout), PathKindName(kind));
      RobotPathOptions path_options;
      path_options.kind = kind;
      path_options.umbmark_side_m = 1.5;
      const RobotPath path = BuildRobotPath(world, path_options);
      const auto problem = CheckPathPlacement(world, RobotOptions{}, path, &rig);
      CHECK_FALSE(problem);
      if (problem)
        FAIL_CHECK(problem->section + "." + problem->problem.key + ": " + problem->problem.message);
    }
  }
}

TEST_CASE("a body wider than the corridor is refused at robot.body_width_m", "[sim][placement]") {
  const worlds::World world = Corridor(12.0, 0, 1.9);
  const RobotPath path = BuildRobotPath(world, RobotPathOptions{});
  RobotOptions robot;
  robot.body_width_m = 2.0;
  const auto problem = CheckPathPlacement(world, robot, path, nullptr);
  CheckRefusedAt(problem, "robot", "body_width_m",
                 Catch::Contains("intersects a wall") && Catch::Contains("0 m along the path") &&
                     Catch::Contains("(got 2)"));
}

TEST_CASE("a body that only hits a wall while it turns is refused at robot.body_length_m",
          "[sim][placement]") {
  const worlds::World world = Corridor(12.0);
  RobotPathOptions path_options;
  path_options.end_margin_m = 1.5;  // room for the body's 1.235 m behind the axle
  const RobotPath path = BuildRobotPath(world, path_options);
  RobotOptions robot;
  robot.body_length_m = 2.4;  // its corners sweep 1.25 m about the axle: the walls are 1.2 m off
  // Standing at the start and driving the first leg it fits; the first turn, 9 m along the path,
  // does not.
  CHECK_FALSE(CheckPathPlacement(world, robot, StandAt(path.world_from_start), nullptr));
  const auto problem = CheckPathPlacement(world, robot, path, nullptr);
  CheckRefusedAt(problem, "robot", "body_length_m",
                 Catch::Contains("9 m along the path") && Catch::Contains("(got 2.4)"));
}

TEST_CASE("a camera above the ceiling is refused at its mount", "[sim][placement]") {
  const worlds::World world = Corridor(12.0);
  const RobotPath path = BuildRobotPath(world, RobotPathOptions{});
  render::Mount mount;
  mount.z_m = 3.0;
  const render::RigOptions rig = WithMount("front", mount);
  const auto problem = CheckPathPlacement(world, RobotOptions{}, path, &rig);
  CheckRefusedAt(problem, "sensors", "front.mount",
                 Catch::Contains("above the ceiling (2.7 m high)"));
}

TEST_CASE("a camera 0.6 m to the side that meets the end wall only during a turn is refused",
          "[sim][placement]") {
  const worlds::World world = Corridor(12.0);
  RobotPathOptions path_options;
  path_options.end_margin_m = 0.5;
  const RobotPath path = BuildRobotPath(world, path_options);
  REQUIRE(path.waypoints.size() >= 1);
  // The side that swings forward, towards the end wall, in the path's first turn.
  const double turn = path.waypoints.front().turn_rad;
  REQUIRE(turn != 0.0);
  render::Mount mount;
  mount.x_m = 0.0;
  mount.y_m = turn > 0 ? -0.6 : 0.6;
  mount.z_m = 0.5;
  const render::RigOptions rig = WithMount("lateral", mount);
  // The start-pose check passes: the camera is 0.6 m from the axis of a 2.4 m corridor.
  CHECK_FALSE(render::CheckCameraPlacement(world, rig, SE3::FromSE2(path.world_from_start)));
  const auto problem = CheckPathPlacement(world, RobotOptions{}, path, &rig);
  CheckRefusedAt(problem, "sensors", "lateral.mount", Catch::Contains("inside a wall"));
  // The other side swings away from the wall and fits.
  mount.y_m = -mount.y_m;
  const render::RigOptions other = WithMount("lateral", mount);
  CHECK_FALSE(CheckPathPlacement(world, RobotOptions{}, path, &other));
}

TEST_CASE("a camera 1 m ahead of the axle that reaches the end wall at a turnaround is refused",
          "[sim][placement]") {
  // A 5 m corridor's round trip turns 1 m before the end wall: the optical centre touches the
  // wall's face, closer than the near plane, and rendered black frames until this was checked.
  const worlds::World world = Corridor(5.0);
  const RobotPath path = BuildRobotPath(world, RobotPathOptions{});
  render::Mount mount;
  mount.x_m = 1.0;
  mount.z_m = 0.45;
  const render::RigOptions rig = WithMount("front", mount);
  CHECK_FALSE(render::CheckCameraPlacement(world, rig, SE3::FromSE2(path.world_from_start)));
  const auto problem = CheckPathPlacement(world, RobotOptions{}, path, &rig);
  CheckRefusedAt(problem, "sensors", "front.mount", Catch::Contains("it would see through it"));
  // The same camera 0.7 m ahead keeps a clearance of 0.3 m and fits.
  mount.x_m = 0.7;
  const render::RigOptions shorter = WithMount("front", mount);
  CHECK_FALSE(CheckPathPlacement(world, RobotOptions{}, path, &shorter));
}

TEST_CASE("a camera closer to a wall, the floor or the ceiling than its near plane is refused",
          "[sim][placement]") {
  const worlds::World world = Corridor(12.0);
  const SE3 robot = SE3::FromSE2(SE2(6.0, 0.0, 0.0));
  for (const auto& [y_m, z_m, what] :
       {std::tuple{1.17, 0.5, "of a wall"},  // inner face y = 1.2
        std::tuple{0.0, 2.66, "ceiling"}, std::tuple{0.0, 0.03, "floor"}}) {
    CAPTURE(y_m, z_m);
    render::Mount mount;
    mount.y_m = y_m;
    mount.z_m = z_m;
    const render::RigOptions rig = WithMount("front", mount);
    const auto problem = render::CheckCameraPlacement(world, rig, robot);
    REQUIRE(problem);
    CHECK(problem->key == "front.mount");
    CHECK_THAT(problem->message, Catch::Contains(what));
    CHECK(CheckPathPlacement(world, RobotOptions{}, StandAt(SE2(6.0, 0.0, 0.0)), &rig));
    // 2 cm farther in, it is clear.
    mount.y_m = y_m > 0 ? y_m - 0.03 : 0.0;
    mount.z_m = z_m > 1 ? z_m - 0.03 : z_m < 0.1 ? z_m + 0.05 : z_m;
    const render::RigOptions clear = WithMount("front", mount);
    CHECK_FALSE(render::CheckCameraPlacement(world, clear, robot));
  }
}

TEST_CASE("a script that drives into a wall is refused at path.commands", "[sim][placement]") {
  const worlds::World world = Corridor(6.0);
  RobotPath path;
  path.kind = PathKind::kScript;
  path.world_from_start = SE2(4.0, 0.0, 0.0);
  path.commands.push_back(VelocityCommand{2.0, 0.3, 0.0});  // 0.6 m: clear of the wall at 6 m
  CHECK_FALSE(CheckPathPlacement(world, RobotOptions{}, path, nullptr));
  path.commands.push_back(VelocityCommand{10.0, 0.3, 10.0});  // an arc into a side wall
  const auto problem = CheckPathPlacement(world, RobotOptions{}, path, nullptr);
  CheckRefusedAt(problem, "path", "commands", Catch::Contains("intersects a wall"));
}

TEST_CASE("a script spinning for a million seconds is swept once round and stays fast",
          "[sim][placement]") {
  const worlds::World world = Corridor(6.0);
  RobotPath path;
  path.kind = PathKind::kScript;
  path.world_from_start = SE2(3.0, 0.0, 0.0);
  path.commands.push_back(VelocityCommand{1e6, 0.0, 300.0});
  path.commands.push_back(VelocityCommand{1e6, 0.2, 300.0});  // circles of 3.8 cm radius
  CHECK_FALSE(CheckPathPlacement(world, RobotOptions{}, path, nullptr));
}

TEST_CASE("a closed door is a solid for a camera, the corridor in front of it is not",
          "[sim][placement]") {
  const worlds::World world = Corridor(12.0, 6);
  const worlds::Doorway* closed = nullptr;
  for (const worlds::Doorway& d : world.doors) {
    if (d.state == worlds::DoorState::kClosed) closed = &d;
  }
  REQUIRE(closed);
  // The robot stands facing the door's wall, 0.8 m in front of the door's centre.
  const Eigen::Vector2d centre = (closed->column_a + closed->column_b) / 2;
  const Eigen::Vector2d n = closed->inward_normal;
  const SE2 pose(centre + 0.8 * n, std::atan2(-n.y(), -n.x()));
  render::Mount mount;
  mount.z_m = 1.0;
  mount.x_m = 0.7;  // 0.1 m in front of the wall face: free
  const render::RigOptions free_rig = WithMount("front", mount);
  CHECK_FALSE(CheckPathPlacement(world, RobotOptions{}, StandAt(pose), &free_rig));
  mount.x_m = 0.8 + world.options.wall_thickness_m / 2;  // in the leaf
  const render::RigOptions leaf_rig = WithMount("front", mount);
  const auto problem = CheckPathPlacement(world, RobotOptions{}, StandAt(pose), &leaf_rig);
  REQUIRE(problem);
  CHECK(problem->problem.key == "front.mount");
  CHECK_THAT(problem->problem.message, Catch::Contains("door_leaf"));
}

TEST_CASE("the swept chassis boxes are the ones Bullet collides with a wall", "[sim][placement]") {
  // A wide robot beside the left wall (y = 1.2): 1 cm clear, then 1 cm into it.
  const worlds::World world = Corridor(8.0);
  RobotOptions robot;
  robot.body_width_m = 0.6;
  for (const double gap_m : {0.01, -0.01}) {
    CAPTURE(gap_m);
    const SE2 pose(4.0, 1.2 - robot.body_width_m / 2 - gap_m, 0.0);
    const bool refused = CheckPathPlacement(world, robot, StandAt(pose), nullptr).has_value();
    RobotPhysics physics(world, robot, pose);
    physics.Step();
    const bool touching = !physics.contacts().empty();
    CHECK(refused == (gap_m < 0));
    CHECK(touching == refused);
  }
}

}  // namespace
}  // namespace corridorsim::sim
