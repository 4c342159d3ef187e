// Tests sim/robot.cpp: the Bullet Pioneer 3-DX standing, driving and turning the way its wheel
// commands say, meeting walls (reported, never passed through), and stepping deterministically.
#include "sim/robot.h"

#include <cmath>
#include <cstring>
#include <numbers>

#include <catch2/catch.hpp>

#include "tests/support/expect_input_error.h"
#include "tests/support/generated_worlds.h"
#include "worlds/world.h"

namespace corridorsim::sim {
namespace {

// A 12 m straight corridor, 2.4 m wide (walls at y = +-1.2), without doors or furniture.
const worlds::World& Corridor() {
  static const worlds::World world = worlds::Generate(test::BareCorridorOptions(12.0), 3);
  return world;
}

void StepFor(RobotPhysics& robot, double seconds) {
  const auto steps = static_cast<int>(std::lround(seconds * 1000.0));
  for (int i = 0; i < steps; ++i) robot.Step();
}

double Yaw(const SE3& pose) {
  const Eigen::Vector3d x = pose.rotation().col(0);
  return std::atan2(x.y(), x.x());
}

TEST_CASE("the robot stands still on the floor with its frame at floor level", "[sim]") {
  RobotOptions options;
  RobotPhysics robot(Corridor(), options, SE2(2.0, 0.0, 0.0));
  StepFor(robot, 2.0);
  const SE3& pose = robot.state().world_from_robot;
  CHECK(std::abs(pose.translation().z()) < 2e-3);
  CHECK((pose.translation().head<2>() - Eigen::Vector2d(2.0, 0.0)).norm() < 1e-3);
  // Level: the robot's z axis stays within 0.5 deg of vertical.
  CHECK(pose.rotation().col(2).z() > std::cos(0.5 * std::numbers::pi / 180));
  CHECK(robot.contacts().empty());
}

TEST_CASE("equal forward wheel speeds drive straight ahead at wheel radius times speed", "[sim]") {
  RobotOptions options;
  RobotPhysics robot(Corridor(), options, SE2(2.0, 0.0, 0.0));
  const double wheel_rps = 3.0;
  robot.SetWheelSpeeds(wheel_rps, wheel_rps);
  StepFor(robot, 1.0);  // accelerate
  const RobotState a = robot.state();
  StepFor(robot, 2.0);
  const RobotState b = robot.state();
  const double radius = options.wheel_diameter_m / 2;
  const double dx = b.world_from_robot.translation().x() - a.world_from_robot.translation().x();
  CHECK(dx == Approx(wheel_rps * radius * 2.0).epsilon(0.005));
  CHECK(std::abs(b.world_from_robot.translation().y()) < 1e-3);
  CHECK(b.left_wheel_angle_rad - a.left_wheel_angle_rad == Approx(wheel_rps * 2.0).epsilon(0.005));
  CHECK(b.right_wheel_angle_rad - a.right_wheel_angle_rad ==
        Approx(wheel_rps * 2.0).epsilon(0.005));
  CHECK(b.linear_velocity_in_world.x() == Approx(wheel_rps * radius).epsilon(0.005));
}

TEST_CASE("a faster right wheel turns the robot counter-clockwise", "[sim]") {
  RobotOptions options;
  RobotPhysics robot(Corridor(), options, SE2(4.0, 0.0, 0.0));
  const Eigen::Vector2d wheels = WheelSpeedsFor(options, 0.0, 0.5);  // turn in place, 0.5 rad/s
  CHECK(wheels.x() < 0);
  CHECK(wheels.y() > 0);
  robot.SetWheelSpeeds(wheels.x(), wheels.y());
  StepFor(robot, 1.0);
  CHECK(Yaw(robot.state().world_from_robot) > 0.3);
  CHECK(robot.state().angular_velocity_in_world.z() == Approx(0.5).epsilon(0.02));
  // In place: the origin between the wheels stays put.
  CHECK(
      (robot.state().world_from_robot.translation().head<2>() - Eigen::Vector2d(4.0, 0.0)).norm() <
      5e-3);
}

TEST_CASE("a wall stops the robot, is reported as a contact and is never passed through", "[sim]") {
  RobotOptions options;
  // Facing the left wall (y = +1.2) from the corridor axis, full speed ahead for 8 s.
  RobotPhysics robot(Corridor(), options, SE2(6.0, 0.0, std::numbers::pi / 2));
  robot.SetWheelSpeeds(4.0, 4.0);
  bool touched_wall = false;
  double max_front_y = -1e9;
  for (int i = 0; i < 8000; ++i) {
    robot.Step();
    const SE3& pose = robot.state().world_from_robot;
    // The front face of the body, 0.19 m ahead of the axle (body length 0.455, 0.035 behind).
    const Eigen::Vector3d front = pose * Eigen::Vector3d(options.body_length_m / 2 - 0.035, 0, 0.1);
    max_front_y = std::max(max_front_y, front.y());
    for (const Contact& c : robot.contacts()) {
      touched_wall |= c.semantic_class == worlds::SemanticClass::kWall;
    }
  }
  CHECK(touched_wall);
  // The wall face is at y = 1.2: the body may sink into it by Bullet's contact slop only.
  CHECK(max_front_y < 1.2 + 0.01);
  CHECK(max_front_y > 1.2 - 0.01);
}

TEST_CASE("physics steps are deterministic: two robots given the same commands agree bit for bit",
          "[sim]") {
  RobotOptions options;
  options.odometry.diameter_ratio = 1.02;
  RobotPhysics a(Corridor(), options, SE2(2.0, 0.3, 0.1));
  RobotPhysics b(Corridor(), options, SE2(2.0, 0.3, 0.1));
  for (int i = 0; i < 3000; ++i) {
    const double t = i * 1e-3;
    a.SetWheelSpeeds(3.0 + std::sin(t), 3.0 - std::sin(t));
    b.SetWheelSpeeds(3.0 + std::sin(t), 3.0 - std::sin(t));
    a.Step();
    b.Step();
  }
  const SE3& pa = a.state().world_from_robot;
  const SE3& pb = b.state().world_from_robot;
  CHECK(std::memcmp(pa.translation().data(), pb.translation().data(), 3 * sizeof(double)) == 0);
  CHECK(std::memcmp(pa.quaternion().coeffs().data(), pb.quaternion().coeffs().data(),
                    4 * sizeof(double)) == 0);
  CHECK(a.state().left_wheel_angle_rad == b.state().left_wheel_angle_rad);
}

TEST_CASE("a robot options with wheels wider than its body is rejected naming the key", "[sim]") {
  RobotOptions options;
  CHECK_FALSE(options.Check());
  options.wheelbase_m = 0.5;
  const auto problem = options.Check();
  REQUIRE(problem);
  CHECK(problem->key == "body_width_m");
  options = RobotOptions{};
  options.odometry.diameter_ratio = -1;
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "odometry.diameter_ratio");
  options = RobotOptions{};
  options.control_rate_hz = 2000;
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "control_rate_hz");
}

TEST_CASE("any control rate up to the physics rate is accepted; the physics rate is bounded",
          "[sim]") {
  // The driver keeps its own clock (Simulation::control_updates): 300 Hz control over 1000 Hz
  // physics is no error.
  RobotOptions options;
  for (const double ok : {1.0, 50.0, 250.0, 300.0, 1000.0}) {
    options.control_rate_hz = ok;
    CHECK_FALSE(options.Check());
  }
  options.physics_rate_hz = 333.3;
  options.control_rate_hz = 100;
  CHECK_FALSE(options.Check());
  options.physics_rate_hz = std::nan("");
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "physics_rate_hz");
}

}  // namespace
}  // namespace corridorsim::sim
