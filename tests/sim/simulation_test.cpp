// Tests sim/simulation.cpp: the closed loop of physics, path follower, odometry and sensor clock.
// The quality bars of the simulation issue: error-free odometry follows ground truth (0.1 % of
// the distance on 10 m straight, 0.5 deg over a full in-place turn); a wheel-diameter error
// curves the odometry as Borenstein's model predicts; the round trip returns to its start within
// 0.2 m; collisions are reported; stamps are exact multiples of the periods; runs are
// deterministic.
#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include <catch2/catch.hpp>

#include "common/wheel_odometry_model.h"
#include "render/camera_rig.h"
#include "tests/support/generated_worlds.h"
#include "tests/support/uploaded_rig.h"
#include "worlds/world.h"

namespace corridorsim::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// The acceptance numbers.
constexpr double kStraightOdometryFraction = 0.001;  // of the distance driven
constexpr double kTurnOdometryRad = 0.5 * kDeg;      // over a full in-place turn
constexpr double kRoundTripReturnM = 0.2;

// A straight corridor `length_m` long without doors or furniture (walls at y = +-1.2).
worlds::World Corridor(double length_m) {
  return worlds::Generate(test::BareCorridorOptions(length_m), 5);
}

// What a run leaves behind: dead reckoning from the odometry messages next to the truth.
struct Run {
  SE2 odometry_end;
  SE2 truth_end;
  double truth_yaw_change_rad = 0;     // unwrapped
  double odometry_yaw_change_rad = 0;  // unwrapped
  double distance_m = 0;               // driven, truth
  std::vector<WheelOdometry> messages;
  std::vector<Event> events;
  std::vector<TruthSample> truth;  // every physics step
  bool path_done = false;
};

Run Drive(const worlds::World& world, const SimulationOptions& options, RobotPath path,
          bool keep_truth = false) {
  Simulation simulation(world, options, std::move(path));
  Run run;
  SE2 odometry = simulation.path().world_from_start;
  SE2 last_truth = simulation.truth().world_from_robot_2d;
  while (!simulation.finished()) {
    const StepOutput& out = simulation.Step();
    for (const WheelOdometry& m : out.odometry) {
      const SE2 next = ApplyWheelOdometry(odometry, m.left_distance_m, m.right_distance_m,
                                          options.robot.wheelbase_m);
      run.odometry_yaw_change_rad +=
          (m.right_distance_m - m.left_distance_m) / options.robot.wheelbase_m;
      odometry = next;
      run.messages.push_back(m);
    }
    const SE2 truth = out.truth.world_from_robot_2d;
    run.truth_yaw_change_rad += NormalizeAngle(truth.yaw() - last_truth.yaw());
    run.distance_m += (truth.translation() - last_truth.translation()).norm();
    last_truth = truth;
    run.events.insert(run.events.end(), out.events.begin(), out.events.end());
    if (keep_truth) run.truth.push_back(out.truth);
  }
  run.odometry_end = odometry;
  run.truth_end = last_truth;
  run.path_done = simulation.path_done();
  return run;
}

// Straight ahead `length_m` from (1, 0) along +x, then stop.
RobotPath StraightPath(double length_m) {
  RobotPath path;
  path.kind = PathKind::kRoundTrip;
  path.world_from_start = SE2(1.0, 0.0, 0.0);
  path.waypoints.push_back(Waypoint{Eigen::Vector2d(1.0 + length_m, 0.0), 0.0});
  return path;
}

TEST_CASE("error-free odometry follows ground truth within 0.1 % over 10 m of straight driving",
          "[sim]") {
  const worlds::World world = Corridor(14.0);
  SimulationOptions options;
  options.robot.odometry.random_k_m = 0.0;  // no random error (the default has P1's)
  const Run run = Drive(world, options, StraightPath(10.0));
  REQUIRE(run.path_done);
  CHECK(run.distance_m == Approx(10.0).epsilon(0.01));
  const double error = (run.odometry_end.translation() - run.truth_end.translation()).norm();
  CHECK(error < kStraightOdometryFraction * run.distance_m);

  CHECK(std::abs(NormalizeAngle(run.odometry_end.yaw() - run.truth_end.yaw())) < kTurnOdometryRad);
}

TEST_CASE("error-free odometry follows a full in-place turn within 0.5 degrees", "[sim]") {
  const worlds::World world = Corridor(8.0);
  SimulationOptions options;
  options.robot.odometry.random_k_m = 0.0;  // no random error (the default has P1's)
  RobotPath path;
  path.world_from_start = SE2(2.0, 0.0, 0.0);
  path.waypoints.push_back(Waypoint{Eigen::Vector2d(2.3, 0.0), 2 * std::numbers::pi});
  const Run run = Drive(world, options, path);
  REQUIRE(run.path_done);
  CHECK(run.truth_yaw_change_rad == Approx(2 * std::numbers::pi).margin(0.01));
  CHECK(std::abs(run.odometry_yaw_change_rad - run.truth_yaw_change_rad) < kTurnOdometryRad);
}

TEST_CASE("a wheel-diameter error E_d curves the odometry of a straight drive as predicted",
          "[sim]") {
  // Borenstein: the real wheels are D_L = 2D/(E_d+1), D_R = 2D E_d/(E_d+1); the encoders convert
  // with D. Driving straight s metres, the right encoder reports s (E_d+1)/(2 E_d) and the left
  // s (E_d+1)/2, so dead reckoning turns by (s_r - s_l)/b = s (E_d+1)/2 (1/E_d - 1)/b.
  const worlds::World world = Corridor(14.0);
  SimulationOptions options;
  options.robot.odometry.random_k_m = 0.0;  // no random error (the default has P1's)
  const double e_d = 1.01;
  options.robot.odometry.diameter_ratio = e_d;
  const Run run = Drive(world, options, StraightPath(10.0));
  REQUIRE(run.path_done);
  const double s = run.distance_m;
  const double predicted_yaw = s * (e_d + 1) / 2 * (1 / e_d - 1) / options.robot.wheelbase_m;
  CHECK(predicted_yaw < -0.25);  // about -17 deg: clockwise
  CHECK(run.odometry_yaw_change_rad == Approx(predicted_yaw).epsilon(0.03));
  // A constant-curvature arc: it ends to the right of the truth by about s * yaw / 2.
  CHECK(run.odometry_end.y() - run.truth_end.y() == Approx(s * predicted_yaw / 2).epsilon(0.05));
  // The truth itself stays straight: the driver steers from ground truth.
  CHECK(std::abs(run.truth_end.y()) < 0.01);
}

TEST_CASE("the round trip returns to within 0.2 m of its start without touching a wall", "[sim]") {
  const worlds::World world = Corridor(16.0);
  SimulationOptions options;
  const RobotPath path = BuildRobotPath(world, options.robot_path);
  const SE2 start = path.world_from_start;
  const Run run = Drive(world, options, path, true);
  REQUIRE(run.path_done);
  CHECK((run.truth_end.translation() - start.translation()).norm() < kRoundTripReturnM);
  CHECK(run.distance_m > 2 * (16.0 - 2 * options.robot_path.end_margin_m) - 0.1);
  for (const Event& e : run.events) {
    CHECK(e.kind != EventKind::kCollisionBegin);
  }
  // Never through a wall: the robot's origin keeps its half width from both walls (y = +-1.2).
  double max_abs_y = 0;
  for (const TruthSample& t : run.truth) {
    max_abs_y = std::max(max_abs_y, std::abs(t.world_from_robot_2d.y()));
  }
  CHECK(max_abs_y < 1.2 - 0.381 / 2);
}

TEST_CASE("driving into the end wall reports a collision and never passes through it", "[sim]") {
  const worlds::World world = Corridor(6.0);
  SimulationOptions options;
  RobotPath path;
  path.kind = PathKind::kScript;
  path.world_from_start = SE2(4.0, 0.0, 0.0);
  path.commands.push_back(VelocityCommand{12.0, 0.3, 0.0});  // 3.6 m ahead: the wall is at 6 m
  const Run run = Drive(world, options, path, true);
  bool wall = false;
  for (const Event& e : run.events) {
    if (e.kind == EventKind::kCollisionBegin) {
      wall |= e.semantic_class == worlds::SemanticClass::kWall;
      CHECK(e.position_in_world.x() == Approx(6.0).margin(0.02));
    }
  }
  CHECK(wall);
  for (const TruthSample& t : run.truth) {
    // The body's front face is 0.19 m ahead of the axle.
    REQUIRE(t.world_from_robot_2d.x() + 0.19 < 6.0 + 0.01);
  }
}

TEST_CASE("odometry stamps are exact multiples of the period and cover the run", "[sim]") {
  const worlds::World world = Corridor(14.0);
  SimulationOptions options;
  options.robot.odometry.rate_hz = 30.0;  // 33,333,333 ns: not a multiple of the physics step
  options.max_duration_ns = 2 * kNanosecondsPerSecond;
  const Run run = Drive(world, options, StraightPath(10.0));
  const TimeNs period = PeriodFromRateHz(30.0);
  REQUIRE(period == 33'333'333);
  REQUIRE(run.messages.size() == 61);  // stamps 0, T, ..., 60 T <= 2 s
  for (std::size_t k = 0; k < run.messages.size(); ++k) {
    CHECK(run.messages[k].stamp_ns == static_cast<TimeNs>(k) * period);
  }
}

// The truth samples of a run (StepOutput::truth_samples), with each step's end truth.
struct TruthRun {
  std::vector<TruthSample> samples;
  std::vector<TruthSample> step_ends;
  std::vector<TimeNs> odometry_stamps;
};

TruthRun DriveForTruth(const worlds::World& world, const SimulationOptions& options) {
  Simulation simulation(world, options, StraightPath(10.0));
  TruthRun run;
  while (!simulation.finished()) {
    const StepOutput& out = simulation.Step();
    run.samples.insert(run.samples.end(), out.truth_samples.begin(), out.truth_samples.end());
    run.step_ends.push_back(out.truth);
    for (const WheelOdometry& m : out.odometry) run.odometry_stamps.push_back(m.stamp_ns);
  }
  return run;
}

TEST_CASE("the truth comes at every grid and odometry stamp whatever the physics rate", "[sim]") {
  // A physics step that does not divide 10 ms (1001 Hz: 999,001 ns; 333.3 Hz: 3,000,300 ns) once
  // kept the truth only where a step happened to end on the grid: 2 rows instead of 201.
  const worlds::World world = Corridor(14.0);
  const TimeNs grid = PeriodFromRateHz(100.0);
  for (const double physics_hz : {1000.0, 1001.0, 333.3}) {
    for (const double odometry_hz : {50.0, 30.0}) {
      CAPTURE(physics_hz, odometry_hz);
      SimulationOptions options;
      options.robot.physics_rate_hz = physics_hz;
      options.robot.odometry.rate_hz = odometry_hz;
      options.max_duration_ns = 2 * kNanosecondsPerSecond;
      const TruthRun run = DriveForTruth(world, options);
      // Expected: the grid and the odometry stamps in (0, end], each once, in order.
      const TimeNs end = run.step_ends.back().stamp_ns;
      std::vector<TimeNs> expected;
      for (TimeNs t = grid; t <= end; t += grid) expected.push_back(t);
      for (const TimeNs t : run.odometry_stamps) {
        if (t > 0) expected.push_back(t);
      }
      std::sort(expected.begin(), expected.end());
      expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
      std::vector<TimeNs> stamps;
      for (const TruthSample& s : run.samples) stamps.push_back(s.stamp_ns);
      REQUIRE(stamps == expected);
      CHECK(std::count_if(stamps.begin(), stamps.end(), [&](TimeNs t) { return t % grid == 0; }) ==
            end / grid);
      // Each sample lies between the physics states around its stamp (interpolated, not snapped).
      std::size_t k = 0;
      for (const TruthSample& s : run.samples) {
        while (run.step_ends[k].stamp_ns < s.stamp_ns) ++k;
        const TruthSample& after = run.step_ends[k];
        if (after.stamp_ns == s.stamp_ns) {
          CHECK(s.state.world_from_robot.translation() ==
                after.state.world_from_robot.translation());
          continue;
        }
        REQUIRE(k > 0);
        const TruthSample& before = run.step_ends[k - 1];
        const double t = static_cast<double>(s.stamp_ns - before.stamp_ns) /
                         static_cast<double>(after.stamp_ns - before.stamp_ns);
        const Eigen::Vector3d expected_p = (1 - t) * before.state.world_from_robot.translation() +
                                           t * after.state.world_from_robot.translation();
        CHECK((s.state.world_from_robot.translation() - expected_p).norm() < 1e-12);
        CHECK(s.world_from_robot_2d.x() == s.state.world_from_robot.translation().x());
      }
    }
  }
}

TEST_CASE("the truth at 1001 Hz physics follows the 1000 Hz truth within a millimetre", "[sim]") {
  const worlds::World world = Corridor(14.0);
  SimulationOptions options;
  options.max_duration_ns = 4 * kNanosecondsPerSecond;
  const TruthRun reference = DriveForTruth(world, options);
  options.robot.physics_rate_hz = 1001.0;
  const TruthRun other = DriveForTruth(world, options);
  REQUIRE(other.samples.size() == reference.samples.size());
  for (std::size_t k = 0; k < reference.samples.size(); ++k) {
    REQUIRE(other.samples[k].stamp_ns == reference.samples[k].stamp_ns);
    CHECK((other.samples[k].world_from_robot_2d.translation() -
           reference.samples[k].world_from_robot_2d.translation())
              .norm() < 1e-3);
  }
}

TEST_CASE("the driver acts at control_rate_hz whatever the physics rate", "[sim]") {
  // It once acted every round(physics / control) steps: 333.3 Hz physics with 100 Hz control
  // ran it every 3 steps, at 111 Hz.
  const worlds::World world = Corridor(14.0);
  for (const double physics_hz : {1000.0, 1001.0, 333.3, 3000.0}) {
    for (const double control_hz : {100.0, 30.0, 300.0}) {
      if (control_hz > physics_hz) continue;
      CAPTURE(physics_hz, control_hz);
      SimulationOptions options;
      options.robot.physics_rate_hz = physics_hz;
      options.robot.control_rate_hz = control_hz;
      options.max_duration_ns = 2 * kNanosecondsPerSecond;
      REQUIRE_FALSE(options.robot.Check());
      Simulation simulation(world, options, StraightPath(10.0));
      while (!simulation.finished()) simulation.Step();
      const double expected = ToSeconds(simulation.now_ns()) * control_hz;
      CHECK(std::abs(static_cast<double>(simulation.control_updates()) - expected) <= 1.0);
    }
  }
}

TEST_CASE("two simulations with one seed give bit-identical odometry and truth", "[sim]") {
  const worlds::World world = Corridor(14.0);
  SimulationOptions options;
  options.robot.odometry.random_k_m = 1e-4;
  options.robot.odometry.slip_rate_per_m = 0.5;
  options.max_duration_ns = 8 * kNanosecondsPerSecond;
  const Run a = Drive(world, options, StraightPath(10.0), true);
  const Run b = Drive(world, options, StraightPath(10.0), true);
  REQUIRE(a.messages.size() == b.messages.size());
  for (std::size_t k = 0; k < a.messages.size(); ++k) {
    CHECK(std::memcmp(&a.messages[k].left_distance_m, &b.messages[k].left_distance_m,
                      sizeof(double)) == 0);
    CHECK(a.messages[k].right_ticks == b.messages[k].right_ticks);
  }
  REQUIRE(a.truth.size() == b.truth.size());
  CHECK(std::memcmp(a.truth.back().state.world_from_robot.translation().data(),
                    b.truth.back().state.world_from_robot.translation().data(),
                    3 * sizeof(double)) == 0);
  bool slipped = false;
  for (const Event& e : a.events) slipped |= e.kind == EventKind::kSlip;
  CHECK(slipped);
  // Another seed draws other errors.
  options.seed = 2;
  const Run c = Drive(world, options, StraightPath(10.0));
  CHECK(c.odometry_end.x() != a.odometry_end.x());
}

// The default rig with only the front camera on: noise-free, at `rate_hz` from `phase_s`, with
// `model`'s images.
render::RigOptions FrontCameraOnly(double rate_hz, double phase_s, const PinholeRadTan& model) {
  render::RigOptions rig_options = render::RigOptions::Default();
  for (render::CameraOptions& c : rig_options.cameras) {
    c.enabled = c.id == "front";
    c.rate_hz = rate_hz;
    c.phase_s = phase_s;
    c.noise = false;
    c.model = model;
  }
  return rig_options;
}

TEST_CASE("camera frames are stamped phase + n / rate and rendered at the true pose of the stamp",
          "[sim][gl]") {
  const worlds::World world = Corridor(14.0);
  const render::RigOptions rig_options =
      FrontCameraOnly(30.0, 0.005, PinholeRadTan::FromFov(64, 48, 58.0 * kDeg));
  test::UploadedRig uploaded(world, rig_options);
  SimulationOptions options;
  options.max_duration_ns = kNanosecondsPerSecond;
  Simulation simulation(world, options, StraightPath(10.0), &uploaded.rig(), &rig_options);
  std::vector<CameraMessage> frames;
  TruthSample before = simulation.truth();
  while (!simulation.finished()) {
    const StepOutput& out = simulation.Step();
    for (const CameraMessage& m : out.frames) {
      // The stamp lies within this step; the pose is the truth interpolated to it.
      REQUIRE(m.stamp_ns > before.stamp_ns);
      REQUIRE(m.stamp_ns <= out.truth.stamp_ns);
      const double t = static_cast<double>(m.stamp_ns - before.stamp_ns) /
                       static_cast<double>(out.truth.stamp_ns - before.stamp_ns);
      const Eigen::Vector3d expected = (1 - t) * before.state.world_from_robot.translation() +
                                       t * out.truth.state.world_from_robot.translation();
      CHECK((m.world_from_robot.translation() - expected).norm() < 1e-9);
      CHECK(m.frame.rgb.width == 64);
      frames.push_back(m);
    }
    before = out.truth;
  }
  const TimeNs period = PeriodFromRateHz(30.0), phase = FromSeconds(0.005);
  REQUIRE(frames.size() == 30);  // 5 ms + n * 33.33 ms <= 1 s: n = 0..29
  for (std::size_t n = 0; n < frames.size(); ++n) {
    CHECK(frames[n].stamp_ns == phase + static_cast<TimeNs>(n) * period);
    CHECK(frames[n].frame_index == n);
    CHECK(frames[n].truth.camera_id == "front");
  }
}

TEST_CASE("dropped frames are neither rendered nor delivered and each is an event", "[sim][gl]") {
  const worlds::World world = Corridor(14.0);
  render::RigOptions rig_options =
      FrontCameraOnly(50.0, 0.0, PinholeRadTan::FromFov(32, 24, 58.0 * kDeg));
  for (render::CameraOptions& c : rig_options.cameras) c.drop_probability = 0.3;
  test::UploadedRig uploaded(world, rig_options);
  SimulationOptions options;
  options.max_duration_ns = 4 * kNanosecondsPerSecond;
  auto run = [&](std::vector<TimeNs>* delivered, std::vector<TimeNs>* dropped) {
    Simulation simulation(world, options, StraightPath(10.0), &uploaded.rig(), &rig_options);
    while (!simulation.finished()) {
      const StepOutput& out = simulation.Step();
      for (const CameraMessage& m : out.frames) delivered->push_back(m.stamp_ns);
      for (const Event& e : out.events) {
        if (e.kind == EventKind::kFrameDropped) {
          CHECK(e.camera_id == "front");
          dropped->push_back(e.stamp_ns);
        }
      }
    }
  };
  std::vector<TimeNs> delivered, dropped;
  run(&delivered, &dropped);
  // 201 stamps (0 to 4 s at 50 Hz): each either delivered or dropped, never both.
  CHECK(delivered.size() + dropped.size() == 201);
  std::vector<TimeNs> all = delivered;
  all.insert(all.end(), dropped.begin(), dropped.end());
  std::sort(all.begin(), all.end());
  for (std::size_t n = 0; n < all.size(); ++n) CHECK(all[n] == static_cast<TimeNs>(n) * 20'000'000);
  // About 30 % lost: Binomial(201, 0.3) has a standard deviation of 6.5 frames.
  CHECK(dropped.size() > 60 - 26);
  CHECK(dropped.size() < 60 + 26);
  // The same seed loses the same frames.
  std::vector<TimeNs> delivered2, dropped2;
  run(&delivered2, &dropped2);
  CHECK(dropped2 == dropped);
}

}  // namespace
}  // namespace corridorsim::sim
