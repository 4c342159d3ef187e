// Tests sim/path.cpp: the paths BuildRobotPath lays over generated worlds, the errors it reports
// for paths that do not fit, RobotPathOptions::Check and ParseRobotPathOptions, and the
// PathFollower driving a differential-drive robot simulated here (kinematic, 1 kHz, wheel speed
// limits, optionally one wheel larger than the controller believes) at a 100 Hz control rate.
#include "sim/robot_path.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/expect_input_error.h"
#include "tests/support/generated_worlds.h"
#include "worlds/world.h"

namespace corridorsim::sim {
namespace {

using Eigen::Vector2d;
using test::Contains;
using test::InputErrorOf;
using test::OptionsErrorOf;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr TimeNs kControlPeriodNs = 10'000'000;  // 100 Hz follower
constexpr TimeNs kPhysicsPeriodNs = 1'000'000;   // 1 kHz integration

// Tolerances of the requirements (the task's acceptance numbers), in one place.
constexpr double kReturnToleranceM = 0.05;
constexpr double kReturnToleranceRad = 2.0 * kDeg;
constexpr double kMinWallDistanceM = 0.3;
constexpr double kOffsetToleranceM = 0.02;
constexpr double kTurnOvershootRad = 0.5 * kDeg;
constexpr double kNumericSlack = 1e-9;

// Pioneer 3-DX-like differential drive.
struct Plant {
  double track_m = 0.33;           // wheel separation
  double max_wheel_mps = 1.2;      // per wheel; both scale down together (curvature kept)
  double right_wheel_scale = 1.0;  // true/believed right wheel radius (UMBmark type-B error)
};

struct Step {
  TimeNs t_ns = 0;
  SE2 world_from_robot;  // true pose given to the follower
  DriveCommand command;
  double progress = 0.0;
};

struct Run {
  std::vector<Step> steps;  // one per control period
  std::vector<SE2> poses;   // every physics step
  bool done = false;
  SE2 world_from_robot_end;
};

// Exact unicycle motion over dt at constant (v, w): a chord of the arc, in the sinc form that
// stays accurate for tiny w.
SE2 Integrate(const SE2& pose, double v, double w, double dt) {
  const double half = w * dt / 2;
  const double sinc = std::abs(half) < 1e-4 ? 1 - half * half / 6 : std::sin(half) / half;
  const double chord = v * dt * sinc, direction = pose.yaw() + half;
  return SE2(pose.x() + chord * std::cos(direction), pose.y() + chord * std::sin(direction),
             pose.yaw() + w * dt);
}

// Drives `path` from its start until the follower is done (or `max_s` of simulated time).
Run Simulate(const RobotPath& path, const RobotPathOptions& options, const Plant& plant = {},
             double max_s = 2000.0) {
  PathFollower follower(path, options);
  Run run;
  SE2 pose = path.world_from_start;
  DriveCommand command;
  const TimeNs end_ns = FromSeconds(max_s);
  for (TimeNs t = 0; t <= end_ns; t += kPhysicsPeriodNs) {
    if (t % kControlPeriodNs == 0) {
      command = follower.Update(t, pose);
      run.steps.push_back({t, pose, command, follower.progress()});
      if (follower.done()) {
        run.done = true;
        break;
      }
    }
    double right = command.linear_mps + command.angular_rps * plant.track_m / 2;
    double left = command.linear_mps - command.angular_rps * plant.track_m / 2;
    const double fastest = std::max(std::abs(right), std::abs(left));
    if (fastest > plant.max_wheel_mps) {
      right *= plant.max_wheel_mps / fastest;
      left *= plant.max_wheel_mps / fastest;
    }
    right *= plant.right_wheel_scale;
    pose = Integrate(pose, (right + left) / 2, (right - left) / plant.track_m,
                     ToSeconds(kPhysicsPeriodNs));
    run.poses.push_back(pose);
  }
  run.world_from_robot_end = pose;
  return run;
}

double PointSegmentDistance(const Vector2d& p, const Vector2d& a, const Vector2d& b) {
  const Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

double MinWallDistance(const worlds::World& world, const std::vector<SE2>& poses) {
  double nearest = 1e9;
  for (const SE2& pose : poses) {
    for (const worlds::Wall& wall : world.walls) {
      nearest = std::min(nearest, PointSegmentDistance(pose.translation(), wall.start, wall.end));
    }
  }
  return nearest;
}

// One in-place turn of a run: consecutive control steps commanding rotation without motion.
struct TurnPhase {
  std::size_t first = 0, last = 0;  // step indices
  double turned_rad = 0.0;          // yaw change over the phase (unwrapped)
  double overshoot_rad = 0.0;       // furthest the yaw went beyond where the phase ended
  Vector2d p_in_world;
};

std::vector<TurnPhase> TurnPhases(const Run& run) {
  std::vector<TurnPhase> phases;
  const auto& s = run.steps;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (s[k].command.angular_rps == 0.0 || s[k].command.linear_mps != 0.0) continue;
    if (phases.empty() || phases.back().last + 1 != k) {
      phases.push_back({k, k, 0.0, 0.0, s[k].world_from_robot.translation()});
    }
    phases.back().last = k;
  }
  for (TurnPhase& phase : phases) {
    // Yaw after the phase: the pose of the step after its last command.
    const std::size_t end = std::min(phase.last + 1, s.size() - 1);
    std::vector<double> turned{0.0};
    for (std::size_t k = phase.first + 1; k <= end; ++k) {
      turned.push_back(turned.back() + NormalizeAngle(s[k].world_from_robot.yaw() -
                                                      s[k - 1].world_from_robot.yaw()));
    }
    phase.turned_rad = turned.back();
    const double sign = phase.turned_rad >= 0 ? 1.0 : -1.0;
    for (const double t : turned) {
      phase.overshoot_rad = std::max(phase.overshoot_rad, sign * (t - phase.turned_rad));
    }
  }
  return phases;
}

// Largest |change of command| / control period over the run.
double MaxLinearAcceleration(const Run& run) {
  double worst = 0.0;
  for (std::size_t k = 1; k < run.steps.size(); ++k) {
    worst = std::max(
        worst, std::abs(run.steps[k].command.linear_mps - run.steps[k - 1].command.linear_mps) /
                   ToSeconds(kControlPeriodNs));
  }
  return worst;
}

// The farthest the robot got along world x (axis 0) or y (axis 1), from 0.
double Farthest(const Run& run, int axis) {
  double farthest = 0.0;
  for (const SE2& pose : run.poses) farthest = std::max(farthest, pose.translation()[axis]);
  return farthest;
}

double MaxSpeed(const Run& run) {
  double fastest = 0.0;
  for (const Step& s : run.steps) fastest = std::max(fastest, s.command.linear_mps);
  return fastest;
}

// Worlds (generated once per test binary).
const worlds::World& DefaultWorld() { return test::GeneratedWorld(1); }
const worlds::World& LoopWorld() { return test::GeneratedWorld(1, worlds::Layout::kLoop); }
const worlds::World& LTurnWorld() { return test::GeneratedWorld(1, worlds::Layout::kLTurn); }

// A 6 m wide hall: room for Borenstein's 4 m UMBmark square.
const worlds::World& WideWorld() {
  static const worlds::World world = [] {
    worlds::WorldOptions world_options;
    world_options.length_m = 30.0;
    world_options.width_m = 6.0;
    return worlds::Generate(world_options, 1);
  }();
  return world;
}

void RequireReturnsToStart(const RobotPath& path, const Run& run) {
  REQUIRE(run.done);
  const SE2 start = path.world_from_start, end = run.world_from_robot_end;
  INFO("start (" << start.x() << ", " << start.y() << ", " << start.yaw() << "), end (" << end.x()
                 << ", " << end.y() << ", " << end.yaw() << ")");
  CHECK((end.translation() - start.translation()).norm() < kReturnToleranceM);
  CHECK(std::abs(NormalizeAngle(end.yaw() - start.yaw())) < kReturnToleranceRad);
}

TEST_CASE("the default round trip goes to the far end of the corridor and returns to its start",
          "[sim][path]") {
  const worlds::World& world = DefaultWorld();
  const RobotPathOptions options;
  const RobotPath path = BuildRobotPath(world, options);
  CHECK(path.world_from_start.x() == Approx(options.end_margin_m));
  CHECK(path.world_from_start.y() == Approx(0.0).margin(1e-12));
  CHECK(path.world_from_start.yaw() == Approx(0.0).margin(1e-12));
  CHECK(path.length_m() == Approx(2 * (world.options.length_m - 2 * options.end_margin_m)));
  CHECK(path.total_turn_rad() == Approx(2 * std::numbers::pi));

  const Run run = Simulate(path, options);
  RequireReturnsToStart(path, run);
  CHECK(Farthest(run, 0) == Approx(world.options.length_m - options.end_margin_m).margin(0.01));
  CHECK(MinWallDistance(world, run.poses) >= kMinWallDistanceM);
  CHECK(run.steps.back().progress == 1.0);
}

TEST_CASE("cruise speed is speed_mps, never more, and speed ramps stay within the acceleration",
          "[sim][path]") {
  for (const double speed : {0.34, 0.30}) {  // P1, P3
    INFO("speed_mps " << speed);
    RobotPathOptions options;
    options.speed_mps = speed;
    const RobotPath path = BuildRobotPath(DefaultWorld(), options);
    const Run run = Simulate(path, options);
    REQUIRE(run.done);
    CHECK(MaxSpeed(run) == Approx(speed).epsilon(1e-12));
    CHECK(MaxSpeed(run) <= speed);
    CHECK(MaxLinearAcceleration(run) <= options.acceleration_mps2 + kNumericSlack);
    // Speed measured on the simulated robot, physics step to physics step.
    double fastest = 0.0;
    for (std::size_t k = 1; k < run.poses.size(); ++k) {
      fastest =
          std::max(fastest, (run.poses[k].translation() - run.poses[k - 1].translation()).norm() /
                                ToSeconds(kPhysicsPeriodNs));
    }
    CHECK(fastest <= speed + kNumericSlack);
    CHECK(fastest == Approx(speed).epsilon(1e-6));
    // Most of the corridor is driven at cruise speed.
    int cruising = 0;
    for (const Step& s : run.steps) cruising += s.command.linear_mps == speed ? 1 : 0;
    CHECK(cruising * ToSeconds(kControlPeriodNs) * speed > 0.9 * path.length_m());
  }
}

TEST_CASE("turns happen in place at turn_rate_dps with ramps and without overshoot",
          "[sim][path]") {
  RobotPathOptions options;
  const RobotPath path = BuildRobotPath(DefaultWorld(), options);
  const Run run = Simulate(path, options);
  REQUIRE(run.done);
  const std::vector<TurnPhase> phases = TurnPhases(run);
  REQUIRE(phases.size() == 2);
  for (const TurnPhase& phase : phases) {
    CHECK(std::abs(phase.turned_rad) == Approx(std::numbers::pi).margin(0.3 * kDeg));
    CHECK(phase.overshoot_rad <= kTurnOvershootRad);
  }
  // The far turn happens at the far end, the last one at the start.
  CHECK(phases[0].p_in_world.x() == Approx(DefaultWorld().options.length_m - 1.0).margin(0.01));
  CHECK(phases[1].p_in_world.x() == Approx(1.0).margin(0.01));

  const double rate_rps = options.turn_rate_dps * kDeg;
  const double step_rps = options.turn_acceleration_dps2 * kDeg * ToSeconds(kControlPeriodNs);
  double fastest_turn = 0.0, worst_rate_step = 0.0, fastest_turn_while_moving = 0.0;
  for (std::size_t k = 0; k < run.steps.size(); ++k) {
    const DriveCommand& c = run.steps[k].command;
    if (c.linear_mps > 0) {
      fastest_turn_while_moving = std::max(fastest_turn_while_moving, std::abs(c.angular_rps));
    } else {
      fastest_turn = std::max(fastest_turn, std::abs(c.angular_rps));
      if (k > 0) {
        worst_rate_step = std::max(worst_rate_step,
                                   std::abs(c.angular_rps - run.steps[k - 1].command.angular_rps));
      }
    }
  }
  CHECK(fastest_turn == Approx(rate_rps).epsilon(1e-12));
  CHECK(worst_rate_step <= step_rps + kNumericSlack);
  // While driving, only heading corrections (this plant is ideal: none at all).
  CHECK(fastest_turn_while_moving < 0.1 * kDeg);
}

TEST_CASE("a lateral offset is held on the straight legs, left of travel, with a wheel error",
          "[sim][path]") {
  const worlds::World& world = DefaultWorld();
  RobotPathOptions options;
  options.lateral_offset_m = 0.4;
  const RobotPath path = BuildRobotPath(world, options);
  CHECK(path.world_from_start.y() == Approx(0.4));
  Plant plant;
  plant.right_wheel_scale = 1.02;  // 2 % larger right wheel: the robot drifts left if unchecked
  const Run run = Simulate(path, options, plant);
  RequireReturnsToStart(path, run);
  int out_samples = 0, back_samples = 0;
  double worst_m = 0.0;
  for (const SE2& pose : run.poses) {
    // Straight legs: away from the turns at x = 1 and x = 54.
    if (pose.x() < 2.0 || pose.x() > world.options.length_m - 2.0) continue;
    const bool outbound = std::abs(NormalizeAngle(pose.yaw())) < 10 * kDeg;
    const bool back = std::abs(NormalizeAngle(pose.yaw() - std::numbers::pi)) < 10 * kDeg;
    REQUIRE((outbound || back));
    out_samples += outbound ? 1 : 0;
    back_samples += back ? 1 : 0;
    worst_m = std::max(worst_m, std::abs(pose.y() - (outbound ? 0.4 : -0.4)));
  }
  CHECK(out_samples > 100'000);
  CHECK(back_samples > 100'000);
  CHECK(worst_m <= kOffsetToleranceM);
  CHECK(MinWallDistance(world, run.poses) >= kMinWallDistanceM);
}

TEST_CASE("the round trip on an L-turn drives both legs and returns", "[sim][path]") {
  const worlds::World& world = LTurnWorld();
  RobotPathOptions options;
  options.lateral_offset_m = -0.3;
  const RobotPath path = BuildRobotPath(world, options);
  const Run run = Simulate(path, options);
  RequireReturnsToStart(path, run);
  CHECK(Farthest(run, 1) ==
        Approx(world.options.second_length_m - options.end_margin_m).margin(0.01));
  CHECK(MinWallDistance(world, run.poses) >= kMinWallDistanceM);
}

TEST_CASE("the round trip on a T-junction stays in the main corridor", "[sim][path]") {
  worlds::WorldOptions world_options;
  world_options.layout = worlds::Layout::kTJunction;
  const worlds::World world = worlds::Generate(world_options, 1);
  const RobotPathOptions options;
  const RobotPath path = BuildRobotPath(world, options);
  CHECK(path.length_m() == Approx(2 * (world_options.length_m - 2 * options.end_margin_m)));
  const Run run = Simulate(path, options);
  RequireReturnsToStart(path, run);
  for (const SE2& pose : run.poses) REQUIRE(std::abs(pose.y()) < 0.01);
}

TEST_CASE("the loop path goes round the loop layout and closes", "[sim][path]") {
  const worlds::World& world = LoopWorld();
  for (const double offset : {0.0, 0.5}) {
    INFO("lateral_offset_m " << offset);
    RobotPathOptions options;
    options.kind = PathKind::kLoop;
    options.lateral_offset_m = offset;
    options.laps = 2;
    const RobotPath path = BuildRobotPath(world, options);
    const double l = world.options.length_m, l2 = world.options.second_length_m;
    // Left of travel on a counter-clockwise loop is inside the rectangle.
    CHECK(path.length_m() == Approx(2 * 2 * (l - 2 * offset + l2 - 2 * offset)).epsilon(1e-12));
    CHECK(path.total_turn_rad() == Approx(2 * 2 * std::numbers::pi));
    const Run run = Simulate(path, options);
    RequireReturnsToStart(path, run);
    Eigen::AlignedBox2d box;
    for (const SE2& pose : run.poses) box.extend(pose.translation());
    CHECK(box.min().x() == Approx(offset).margin(0.01));
    CHECK(box.min().y() == Approx(offset).margin(0.01));
    CHECK(box.max().x() == Approx(l - offset).margin(0.01));
    CHECK(box.max().y() == Approx(l2 - offset).margin(0.01));
    const std::vector<TurnPhase> phases = TurnPhases(run);
    CHECK(phases.size() == 8);
    for (const TurnPhase& phase : phases) CHECK(phase.turned_rad == Approx(90 * kDeg).margin(0.01));
    CHECK(MinWallDistance(world, run.poses) >= kMinWallDistanceM);
  }
}

TEST_CASE("UMBmark squares have the right sides and turn clockwise or counter-clockwise",
          "[sim][path]") {
  const worlds::World& world = WideWorld();
  for (const PathKind kind : {PathKind::kUmbmarkCw, PathKind::kUmbmarkCcw}) {
    INFO(PathKindName(kind));
    RobotPathOptions options;
    options.kind = kind;
    const RobotPath path = BuildRobotPath(world, options);
    const Run run = Simulate(path, options);
    RequireReturnsToStart(path, run);
    const std::vector<TurnPhase> phases = TurnPhases(run);
    REQUIRE(phases.size() == 4);
    const double sign = kind == PathKind::kUmbmarkCw ? -1.0 : 1.0;
    Vector2d previous = path.world_from_start.translation();
    for (const TurnPhase& phase : phases) {
      CHECK(phase.turned_rad == Approx(sign * 90 * kDeg).margin(0.01));
      CHECK((phase.p_in_world - previous).norm() == Approx(options.umbmark_side_m).margin(0.01));
      previous = phase.p_in_world;
    }
    // First side along +x; the square is centred on the corridor axis.
    CHECK(phases[0].p_in_world.x() - path.world_from_start.x() ==
          Approx(options.umbmark_side_m).margin(0.01));
    Eigen::AlignedBox2d box;
    for (const SE2& pose : run.poses) box.extend(pose.translation());
    CHECK(box.min().y() == Approx(-2.0).margin(0.01));
    CHECK(box.max().y() == Approx(2.0).margin(0.01));
    CHECK(box.min().x() == Approx(options.end_margin_m).margin(0.01));
    CHECK(MinWallDistance(world, run.poses) >= kMinWallDistanceM);
  }
}

TEST_CASE("scripted velocity commands are reproduced in order, then the robot stops",
          "[sim][path]") {
  RobotPathOptions options;
  options.kind = PathKind::kScript;
  options.commands = {{2.0, 0.3, 0.0}, {3.0, 0.0, 30.0}, {1.5, -0.2, -10.0}};
  const RobotPath path = BuildRobotPath(DefaultWorld(), options);
  PathFollower follower(path, options);
  for (TimeNs t = 0; t <= FromSeconds(8.0); t += kControlPeriodNs) {
    const double t_s = ToSeconds(t);
    const DriveCommand c = follower.Update(t, path.world_from_start);
    INFO("t " << t_s << " s");
    if (t_s < 2.0 - 1e-9) {
      CHECK(c.linear_mps == 0.3);
      CHECK(c.angular_rps == 0.0);
    } else if (t_s < 5.0 - 1e-9) {
      CHECK(c.linear_mps == 0.0);
      CHECK(c.angular_rps == Approx(30 * kDeg).epsilon(1e-15));
    } else if (t_s < 6.5 - 1e-9) {
      CHECK(c.linear_mps == -0.2);
      CHECK(c.angular_rps == Approx(-10 * kDeg).epsilon(1e-15));
    } else {
      CHECK(c.linear_mps == 0.0);
      CHECK(c.angular_rps == 0.0);
      CHECK(follower.done());
    }
    CHECK(follower.done() == (t_s >= 6.5 - 1e-9));
  }
  // Driven open loop, the robot ends where the commands integrate to.
  const Run run = Simulate(path, options);
  REQUIRE(run.done);
  SE2 expected = path.world_from_start;
  for (const VelocityCommand& c : options.commands) {
    expected = Integrate(expected, c.linear_mps, c.angular_dps * kDeg, c.duration_s);
  }
  CHECK((run.world_from_robot_end.translation() - expected.translation()).norm() < 1e-9);
  CHECK(std::abs(NormalizeAngle(run.world_from_robot_end.yaw() - expected.yaw())) < 1e-9);
}

TEST_CASE("the follower is a pure function of its inputs", "[sim][path]") {
  RobotPathOptions options;
  options.lateral_offset_m = 0.2;
  const RobotPath path = BuildRobotPath(DefaultWorld(), options);
  Plant plant;
  plant.right_wheel_scale = 0.99;
  const Run a = Simulate(path, options, plant), b = Simulate(path, options, plant);
  REQUIRE(a.steps.size() == b.steps.size());
  for (std::size_t k = 0; k < a.steps.size(); ++k) {
    REQUIRE(a.steps[k].command.linear_mps == b.steps[k].command.linear_mps);
    REQUIRE(a.steps[k].command.angular_rps == b.steps[k].command.angular_rps);
  }
}

TEST_CASE("progress rises from 0 to 1 along the path", "[sim][path]") {
  RobotPathOptions options;
  const RobotPath path = BuildRobotPath(DefaultWorld(), options);
  const Run run = Simulate(path, options);
  REQUIRE(run.done);
  CHECK(run.steps.front().progress == 0.0);
  CHECK(run.steps.back().progress == 1.0);
  for (std::size_t k = 1; k < run.steps.size(); ++k) {
    REQUIRE(run.steps[k].progress >= run.steps[k - 1].progress);
  }
  // Half way in time is about half way in progress (nominal times, not distance only).
  CHECK(run.steps[run.steps.size() / 2].progress == Approx(0.5).margin(0.02));
}

TEST_CASE("BuildRobotPath names the option of a path that does not fit the world", "[sim][path]") {
  const worlds::World& world = DefaultWorld();  // 55 m x 2.4 m straight
  auto problem_of = [&](const worlds::World& w,
                        const std::function<void(RobotPathOptions&)>& change) {
    RobotPathOptions options;
    change(options);
    REQUIRE_FALSE(options.Check());
    return OptionsErrorOf([&] { BuildRobotPath(w, options); });
  };
  OptionsProblem p = problem_of(world, [](RobotPathOptions& o) { o.kind = PathKind::kLoop; });
  CHECK(p.key == "kind");
  CHECK(Contains(p.message, "layout loop"));
  // Borenstein's 4 m square needs a 4.7 m wide corridor.
  p = problem_of(world, [](RobotPathOptions& o) { o.kind = PathKind::kUmbmarkCw; });
  CHECK(p.key == "umbmark_side_m");
  CHECK(Contains(p.message, "at most 1.7 m fits"));
  p = problem_of(world, [](RobotPathOptions& o) { o.lateral_offset_m = 0.9; });
  CHECK(p.key == "lateral_offset_m");
  CHECK(Contains(p.message, "at most 0.85 m"));
  p = problem_of(world, [](RobotPathOptions& o) { o.lateral_offset_m = -0.86; });
  CHECK(p.key == "lateral_offset_m");
  p = problem_of(world, [](RobotPathOptions& o) {
    o.kind = PathKind::kUmbmarkCcw;
    o.umbmark_side_m = 1.5;
    o.lateral_offset_m = 0.2;
  });
  CHECK(p.key == "lateral_offset_m");
  p = problem_of(world, [](RobotPathOptions& o) { o.lateral_offset_m = 1.5; });
  CHECK(p.key == "lateral_offset_m");
  CHECK(Contains(p.message, "outside the corridor"));
  p = problem_of(world, [](RobotPathOptions& o) { o.end_margin_m = 0.2; });
  CHECK(p.key == "end_margin_m");
  CHECK(Contains(p.message, "end wall"));
  p = problem_of(world, [](RobotPathOptions& o) {  // a script starts where the margin says, too
    o.kind = PathKind::kScript;
    o.commands = {{1.0, 0.1, 0.0}};
    o.end_margin_m = 0.1;
  });
  CHECK(p.key == "end_margin_m");
  p = problem_of(world, [](RobotPathOptions& o) { o.end_margin_m = 28.0; });
  CHECK(p.key == "end_margin_m");
  CHECK(Contains(p.message, "no straight leg"));
  // A square longer than the corridor runs into its far end wall.
  p = problem_of(WideWorld(), [](RobotPathOptions& o) {
    o.kind = PathKind::kUmbmarkCw;
    o.end_margin_m = 26.0;
  });
  CHECK(p.key == "umbmark_side_m");
  CHECK(Contains(p.message, "from wall"));
  // The loop's inner walls: an offset that fits the width fits everywhere on the loop.
  p = problem_of(LoopWorld(), [](RobotPathOptions& o) {
    o.kind = PathKind::kLoop;
    o.lateral_offset_m = 0.86;
  });
  CHECK(p.key == "lateral_offset_m");

  // What just fits, fits.
  for (const double offset : {0.85, -0.85}) {
    RobotPathOptions options;
    options.lateral_offset_m = offset;
    CHECK_NOTHROW(BuildRobotPath(world, options));
  }
  RobotPathOptions square;
  square.kind = PathKind::kUmbmarkCcw;
  square.umbmark_side_m = 1.7;
  CHECK_NOTHROW(BuildRobotPath(world, square));
}

TEST_CASE("RobotPathOptions::Check names the bad option", "[sim][path]") {
  CHECK_FALSE(RobotPathOptions{}.Check());
  auto problem_of = [](const std::function<void(RobotPathOptions&)>& change) {
    RobotPathOptions options;
    change(options);
    const auto problem = options.Check();
    REQUIRE(problem);
    return *problem;
  };
  OptionsProblem p = problem_of([](RobotPathOptions& o) { o.speed_mps = -0.3; });
  CHECK(p.key == "speed_mps");
  CHECK(Contains(p.message, "got -0.3"));
  CHECK(problem_of([](RobotPathOptions& o) { o.speed_mps = 2.0; }).key == "speed_mps");
  CHECK(problem_of([](RobotPathOptions& o) { o.acceleration_mps2 = 0; }).key ==
        "acceleration_mps2");
  CHECK(problem_of([](RobotPathOptions& o) { o.turn_rate_dps = 0; }).key == "turn_rate_dps");
  CHECK(problem_of([](RobotPathOptions& o) { o.turn_acceleration_dps2 = -1; }).key ==
        "turn_acceleration_dps2");
  CHECK(problem_of([](RobotPathOptions& o) { o.end_margin_m = -1; }).key == "end_margin_m");
  CHECK(problem_of([](RobotPathOptions& o) { o.laps = 0; }).key == "laps");
  CHECK(problem_of([](RobotPathOptions& o) { o.umbmark_side_m = 0; }).key == "umbmark_side_m");
  p = problem_of([](RobotPathOptions& o) { o.kind = PathKind::kScript; });
  CHECK(p.key == "commands");
  CHECK(Contains(p.message, "at least one command"));
  p = problem_of([](RobotPathOptions& o) { o.commands = {{1.0, 0.1, 0.0}}; });
  CHECK(p.key == "commands");
  CHECK(Contains(p.message, "only kind script"));
  p = problem_of([](RobotPathOptions& o) {
    o.kind = PathKind::kScript;
    o.commands = {{1.0, 0.1, 0.0}, {0.0, 0.1, 0.0}};
  });
  CHECK(p.key == "commands");
  CHECK(Contains(p.message, "row 2: duration_s"));
  p = problem_of([](RobotPathOptions& o) {
    o.kind = PathKind::kScript;
    o.commands = {{1.0, 0.1, 400.0}};
  });
  CHECK(Contains(p.message, "row 1: angular_dps"));
}

TEST_CASE("script rows are bounded: each lasts at least 1 ms, together at most the longest run",
          "[sim][path]") {
  auto problem_of = [](std::vector<VelocityCommand> commands) {
    RobotPathOptions options;
    options.kind = PathKind::kScript;
    options.commands = std::move(commands);
    return options.Check();
  };
  // 1e-12 s rounds to 0 ns: a command that is never driven.
  auto p = problem_of({{1.0, 0.1, 0.0}, {1e-12, 0.1, 0.0}});
  REQUIRE(p);
  CHECK(p->key == "commands");
  CHECK(Contains(p->message, "row 2: duration_s must lie in [0.001, 1e+06] s (got 1e-12)"));
  CHECK_FALSE(problem_of({{1e-3, 0.1, 0.0}}));
  // Each row within 1e6 s, but their sum (a run's end) beyond it.
  p = problem_of({{6e5, 0.1, 0.0}, {6e5, 0.1, 0.0}});
  REQUIRE(p);
  CHECK(Contains(p->message, "row 2: the commands up to here last 1.2e+06 s"));
  CHECK_FALSE(problem_of(std::vector<VelocityCommand>(10000, {1.0, 0.1, 0.0})));
  p = problem_of(std::vector<VelocityCommand>(10001, {1.0, 0.1, 0.0}));
  REQUIRE(p);
  CHECK(Contains(p->message, "at most 10000 rows (got 10001)"));
}

TEST_CASE("a path whose nominal time exceeds the longest run is refused at laps", "[sim][path]") {
  RobotPathOptions options;
  options.kind = PathKind::kLoop;
  options.speed_mps = 0.01;
  options.laps = 1000;  // a run until the path is done would last weeks of simulated time
  try {
    BuildRobotPath(LoopWorld(), options);
    FAIL("a path of more than 1e6 s was built");
  } catch (const OptionsError& e) {
    CHECK(e.problem().key == "laps");
    CHECK(Contains(e.problem().message, "more than the longest run (1e+06 s)"));
  }
  options.laps = 1;
  CHECK_NOTHROW(BuildRobotPath(LoopWorld(), options));
}

TEST_CASE("ParseRobotPathOptions reads every key and rejects bad input naming the key",
          "[sim][path]") {
  auto parse = [](const std::string& text) {
    const YamlDocument doc = YamlDocument::FromString(text, "path.yaml");
    YamlMap map(doc, doc.root["path"], "path", nullptr);
    RobotPathOptions options;
    ParseRobotPathOptions(map, options);
    return options;
  };
  const RobotPathOptions o = parse(
      "path:\n  kind: script\n  speed_mps: 0.3\n  acceleration_mps2: 0.5\n  turn_rate_dps: 45\n"
      "  turn_acceleration_dps2: 120\n  lateral_offset_m: -0.2\n  end_margin_m: 1.5\n  laps: 3\n"
      "  umbmark_side_m: 1.6\n  commands: [[2, 0.3, 0], [1.5, 0, -20]]\n");
  CHECK(o.kind == PathKind::kScript);
  CHECK(o.speed_mps == 0.3);
  CHECK(o.acceleration_mps2 == 0.5);
  CHECK(o.turn_rate_dps == 45.0);
  CHECK(o.turn_acceleration_dps2 == 120.0);
  CHECK(o.lateral_offset_m == -0.2);
  CHECK(o.end_margin_m == 1.5);
  CHECK(o.laps == 3);
  CHECK(o.umbmark_side_m == 1.6);
  REQUIRE(o.commands.size() == 2);
  CHECK(o.commands[1].duration_s == 1.5);
  CHECK(o.commands[1].linear_mps == 0.0);
  CHECK(o.commands[1].angular_dps == -20.0);
  for (const auto& [kind_name, kind] :
       std::vector<std::pair<std::string, PathKind>>{{"round_trip", PathKind::kRoundTrip},
                                                     {"loop", PathKind::kLoop},
                                                     {"umbmark_cw", PathKind::kUmbmarkCw},
                                                     {"umbmark_ccw", PathKind::kUmbmarkCcw}}) {
    CHECK(parse("path:\n  kind: " + kind_name + "\n").kind == kind);
    CHECK(PathKindName(kind) == kind_name);
  }

  InputError e = InputErrorOf([&] { parse("path:\n  speed_mps: 0.3\n  sped_mps: 0.4\n"); });
  CHECK(e.key() == "path.sped_mps");
  CHECK(e.location().line == 3);
  CHECK(Contains(e.message(), "unknown key"));
  e = InputErrorOf([&] { parse("path:\n  kind: zigzag\n"); });
  CHECK(e.key() == "path.kind");
  CHECK(Contains(e.message(), "round_trip, loop, umbmark_cw, umbmark_ccw, script"));
  e = InputErrorOf([&] { parse("path:\n  speed_mps: fast\n"); });
  CHECK(e.key() == "path.speed_mps");
  e = InputErrorOf([&] { parse("path:\n  kind: script\n  commands:\n    - [1, 0.2]\n"); });
  CHECK(e.key() == "path.commands");
  CHECK(e.location().line == 4);
  CHECK(Contains(e.message(), "row 1"));
  // A negative speed parses; Check() rejects it at its key.
  const auto problem = parse("path:\n  speed_mps: -0.34\n").Check();
  REQUIRE(problem);
  CHECK(problem->key == "speed_mps");
}

}  // namespace
}  // namespace corridorsim::sim
