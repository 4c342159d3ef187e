#include "harness/workbench/dataset.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <string>

#include "common/error.h"
#include "common/random.h"
#include "harness/run/simulation_setup.h"
#include "harness/workbench/dataset_internal.h"

// `dataset`'s robot poses (dataset.h: DatasetPoses): evenly spaced along the scenario's path,
// uniform in the corridor, or aimed at door plates (`--poses path|random|plates`).

namespace corridorsim {
namespace {

using dataset_internal::kCommandLine;
using Eigen::Vector2d;
using Eigen::Vector3d;

// M poses at the centres of M equal parts of the path's legs (start -> waypoint 1 -> ...), each
// heading along its leg: evenly spaced, and never two at a round trip's turning point.
std::vector<SE2> PathPoses(const Scenario& scenario, const worlds::World& world,
                           const render::RigOptions& rig, int count) {
  if (scenario.robot_path.kind == sim::PathKind::kScript) {
    throw InputError(kCommandLine, "--poses",
                     "path: the scenario's path is a script of velocity commands, which has no "
                     "legs to space poses along (use --poses random)");
  }
  const sim::RobotPath path = BuildScenarioRobotPath(scenario, world);
  if (auto problem = sim::CheckPathPlacement(world, scenario.robot, path, &rig)) {
    throw LocateProblem(scenario, problem->section, problem->problem);
  }
  struct Leg {
    Vector2d from, to;
    double length_m;
  };
  std::vector<Leg> legs;
  Vector2d at = path.world_from_start.translation();
  double total_m = 0.0;
  for (const sim::Waypoint& w : path.waypoints) {
    const double length = (w.p_in_world - at).norm();
    if (length > 0.0) legs.push_back(Leg{at, w.p_in_world, length});
    total_m += length;
    at = w.p_in_world;
  }
  if (legs.empty()) {
    throw LocateProblem(scenario, "path",
                        OptionsProblem{"kind", "the path has no leg to place dataset poses on"});
  }
  std::vector<SE2> poses;
  std::size_t leg = 0;
  double leg_start_m = 0.0;
  for (int i = 0; i < count; ++i) {
    const double s = total_m * (i + 0.5) / count;
    while (leg + 1 < legs.size() && s > leg_start_m + legs[leg].length_m) {
      leg_start_m += legs[leg].length_m;
      ++leg;
    }
    const Leg& l = legs[leg];
    const Vector2d direction = (l.to - l.from) / l.length_m;
    const Vector2d p = l.from + direction * std::min(s - leg_start_m, l.length_m);
    poses.emplace_back(p.x(), p.y(), std::atan2(direction.y(), direction.x()));
  }
  return poses;
}

// `count` poses from `draw` (none: a draw that missed its target), each drawn again while its
// chassis or cameras collide (CheckPosePlacement, as snapshot checks --pose); a pose that finds
// no clear draw in kMaxPoseTries is refused at --poses with `refusal`.
std::vector<SE2> DrawClearPoses(const Scenario& scenario, const worlds::World& world,
                                const render::RigOptions& rig, int count,
                                const std::function<std::optional<SE2>()>& draw,
                                const std::string& refusal) {
  std::vector<SE2> poses;
  for (int i = 0; i < count; ++i) {
    bool placed = false;
    for (int attempt = 0; attempt < kMaxPoseTries && !placed; ++attempt) {
      const std::optional<SE2> pose = draw();
      if (pose && !CheckPosePlacement(world, scenario, rig, *pose)) {
        poses.push_back(*pose);
        placed = true;
      }
    }
    if (!placed) throw InputError(kCommandLine, "--poses", refusal);
  }
  return poses;
}

// Uniform over the corridor segments' floor rectangles (a segment drawn in proportion to its
// area; where two overlap at a junction the overlap is twice as likely), yaw uniform; a pose whose
// chassis or cameras collide (CheckPosePlacement, as snapshot checks --pose) is drawn again.
std::vector<SE2> RandomPoses(const Scenario& scenario, const worlds::World& world,
                             const render::RigOptions& rig, int count) {
  RandomStream rng(world.seed, 0, "dataset.poses");
  std::vector<double> cumulative_area;
  double area = 0.0;
  for (const worlds::CorridorSegment& s : world.segments) {
    area += (s.end - s.start).norm() * s.width_m;
    cumulative_area.push_back(area);
  }
  CheckOrDie(area > 0.0, "RandomPoses", "a world without corridor floor");
  const auto draw = [&]() -> std::optional<SE2> {
    const double pick = rng.Uniform(0.0, area);
    const std::size_t k = std::min<std::size_t>(
        std::upper_bound(cumulative_area.begin(), cumulative_area.end(), pick) -
            cumulative_area.begin(),
        world.segments.size() - 1);
    const worlds::CorridorSegment& s = world.segments[k];
    const Vector2d along = s.direction();
    const Vector2d left(-along.y(), along.x());
    // One draw per statement (a call's arguments are evaluated in the compiler's order), in
    // the order GCC took them: across, then along.
    const double across = rng.Uniform(-0.5 * s.width_m, 0.5 * s.width_m);
    const double distance = rng.Uniform(0.0, (s.end - s.start).norm());
    const Vector2d p = s.start + along * distance + left * across;
    return SE2(p.x(), p.y(), rng.Uniform(-std::numbers::pi, std::numbers::pi));
  };
  return DrawClearPoses(scenario, world, rig, count, draw,
                        "random: no pose of world seed " + std::to_string(world.seed) +
                            " keeps the robot and its cameras clear of the walls in " +
                            std::to_string(kMaxPoseTries) +
                            " draws (a corridor too narrow for the robot?)");
}

// The camera's optical centre must lie inside a corridor segment, 0.15 m from its walls and ends.
bool InsideCorridor(const worlds::World& world, const Vector2d& p) {
  for (const worlds::CorridorSegment& s : world.segments) {
    const Vector2d d = s.direction();
    const Vector2d n(-d.y(), d.x());
    const double along = (p - s.start).dot(d), across = (p - s.start).dot(n);
    if (along >= 0.15 && along <= (s.end - s.start).norm() - 0.15 &&
        std::abs(across) <= s.width_m / 2 - 0.15) {
      return true;
    }
  }
  return false;
}

// Lateral views of door plates (P1's reading task, what `train-detectors` learns from): each
// frame aims the lateral camera at a plate, or with probability kAimDistractorFraction at a
// poster or notice board with printed digits (hard negatives). The camera stands 0.4-3.5 m from
// the target, up to 50 deg off its normal, inside the corridor, and looks at it +-30 deg; the
// robot's pose follows from the camera's mount. A pose whose chassis or cameras collide is drawn
// again, target included.
std::vector<SE2> PlatePoses(const Scenario& scenario, const worlds::World& world,
                            const render::RigOptions& rig, int count) {
  const render::CameraOptions* lateral = nullptr;
  for (const render::CameraOptions& c : rig.cameras) {
    if (c.id == "lateral" && c.enabled) lateral = &c;
  }
  if (!lateral) {
    throw InputError(kCommandLine, "--poses",
                     "plates: aims the lateral camera, which is not among the dataset's cameras "
                     "(sensors.lateral.enabled, --cameras)");
  }
  std::vector<const worlds::Distractor*> printed;
  for (const worlds::Distractor& d : world.distractors) {
    if (!d.text.empty()) printed.push_back(&d);
  }
  if (world.plates.empty()) {
    throw InputError(kCommandLine, "--poses",
                     "plates: world seed " + std::to_string(world.seed) +
                         " has no door plate to aim at (world.plates)");
  }
  RandomStream rng(world.seed, 0, "dataset.poses");
  const Vector2d mount(lateral->mount.x_m, lateral->mount.y_m);
  const auto pick = [&](std::size_t n) {
    return std::size_t(rng.UniformInt(0, static_cast<std::int64_t>(n) - 1));
  };
  const auto draw = [&]() -> std::optional<SE2> {
    Vector3d target, normal;
    if (!printed.empty() && rng.Bernoulli(kAimDistractorFraction)) {
      const worlds::Distractor& d = *printed[pick(printed.size())];
      target = d.center + d.normal * (d.size_m.y() / 2);
      normal = d.normal;
    } else {
      const worlds::DoorPlate& p = world.plates[pick(world.plates.size())];
      target = p.center;
      normal = p.normal;
    }
    const Vector2d n = normal.head<2>().normalized();
    const Vector2d t(-n.y(), n.x());
    const double distance = rng.Uniform(0.4, 3.5);
    const double off = rng.Uniform(-50.0, 50.0) * std::numbers::pi / 180.0;
    const double aim_error = rng.Uniform(-30.0, 30.0) * std::numbers::pi / 180.0;
    const Vector2d camera = target.head<2>() + distance * (std::cos(off) * n + std::sin(off) * t);
    if (!InsideCorridor(world, camera)) return std::nullopt;
    const Vector2d to_target = target.head<2>() - camera;
    // The camera looks along the robot's heading + its mount's yaw, from (x, y) on the robot.
    const double robot_yaw = std::atan2(to_target.y(), to_target.x()) + aim_error -
                             lateral->mount.yaw_deg * std::numbers::pi / 180.0;
    const Vector2d robot = camera - Eigen::Rotation2Dd(robot_yaw) * mount;
    return SE2(robot.x(), robot.y(), std::atan2(std::sin(robot_yaw), std::cos(robot_yaw)));
  };
  return DrawClearPoses(scenario, world, rig, count, draw,
                        "plates: no view of a plate of world seed " + std::to_string(world.seed) +
                            " keeps the robot and its cameras clear of the walls in " +
                            std::to_string(kMaxPoseTries) + " draws");
}

}  // namespace

std::vector<SE2> DatasetPoses(const Scenario& scenario, const worlds::World& world,
                              const render::RigOptions& rig, DatasetPoseMode mode, int count) {
  switch (mode) {
    case DatasetPoseMode::kPath:
      return PathPoses(scenario, world, rig, count);
    case DatasetPoseMode::kPlates:
      return PlatePoses(scenario, world, rig, count);
    case DatasetPoseMode::kRandom:
      break;
  }
  return RandomPoses(scenario, world, rig, count);
}

}  // namespace corridorsim
