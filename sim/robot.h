#pragma once
// The robot: a Pioneer 3-DX-like differential-drive base simulated with Bullet (the platform of
// all three papers), and the static collision geometry of the world it drives in.
//
// Bodies: a chassis (box), two driven wheels on motorised hinge constraints, a rear caster (a
// sphere on a ball joint, so it rolls freely in every direction). The wheels touch the floor as
// spheres of the wheel radius: the contact is one point in the wheel's mid-plane, so the wheel
// rolls on exactly its radius and the contact wheelbase is exactly the axle's; friction limits
// traction, so wheels can slip. Wheels and caster collide with the floor only; the chassis
// carries the robot's full footprint (wheels included) and collides with walls, door leaves and
// furniture, not with the floor it never touches. A fresh Bullet world is built per run, stepped at
// a fixed rate with deterministic overlapping pairs (DEPENDENCIES.md: byte-identical trajectories).

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/error.h"
#include "common/io/yaml_reader.h"
#include "common/options_table.h"
#include "common/pose.h"
#include "common/time.h"
#include "sim/odometry.h"
#include "worlds/world.h"

namespace corridorsim::sim {

/// The robot's description (scenario key `robot`). Defaults: Pioneer 3-DX.
struct RobotOptions {
  double body_length_m = 0.455;     // overall, along x
  double body_width_m = 0.381;      // overall, wheels included
  double body_height_m = 0.237;     // floor to top plate
  double mass_kg = 9.0;             // whole robot
  double wheel_diameter_m = 0.195;  // nominal (what odometry and the controller assume)
  double wheel_width_m = 0.047;
  double wheelbase_m = 0.33;         // nominal distance between the wheels' mid-planes
  double wheel_friction = 1.0;       // Coulomb coefficient of the wheel-floor contact
  double max_wheel_torque_nm = 4.0;  // per wheel motor
  double max_wheel_speed_rps = 8.0;  // per wheel motor, rad/s (about 0.78 m/s)
  double physics_rate_hz = 1000.0;   // fixed physics step
  double control_rate_hz = 100.0;    // path follower and motor commands
  OdometryOptions odometry;          // `robot.odometry`: encoders and their errors

  /// The first problem (key relative to `robot`, e.g. "wheelbase_m"), or nothing.
  std::optional<OptionsProblem> Check() const;
  TimeNs physics_step_ns() const { return PeriodFromRateHz(physics_rate_hz); }
};

/// The keys of `robot:` (parsing, bounds, echo, docs).
const OptionTable<RobotOptions>& RobotOptionsTable();

/// One box of the chassis' collision shape, axis-aligned in the robot frame R (m).
struct ChassisBox {
  Eigen::Vector3d center_in_robot = Eigen::Vector3d::Zero();
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();
};

/// The boxes RobotPhysics builds the chassis from (the body, then the right and left wheels'
/// footprint): what meets the world's solids (the placement check sweeps them along the path).
std::vector<ChassisBox> ChassisBoxes(const RobotOptions& options);

/// A contact of the robot's chassis with a world object (walls, doors, furniture).
struct Contact {
  int instance_id = 0;  // World id of the object
  worlds::SemanticClass semantic_class = worlds::SemanticClass::kUnknown;
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();  // deepest contact point, m
  double depth_m = 0.0;  // penetration (positive) at that point
};

/// The true state of the robot after a physics step.
struct RobotState {
  SE3 world_from_robot;  // robot frame R: floor, between the wheels
  Eigen::Vector3d linear_velocity_in_world = Eigen::Vector3d::Zero();   // of R's origin, m/s
  Eigen::Vector3d angular_velocity_in_world = Eigen::Vector3d::Zero();  // rad/s
  double left_wheel_angle_rad = 0.0;  // cumulative rotation, positive rolls forward
  double right_wheel_angle_rad = 0.0;
};

/// The Bullet world with the robot in it. Not copyable; one per run.
class RobotPhysics {
 public:
  /// Builds the world's static collision boxes and a floor plane, and the robot standing at
  /// `world_from_robot_start` (planar). The robot's real wheels follow `options.odometry`'s
  /// systematic errors (RealWheelGeometry); the nominal values stay what the controller uses.
  RobotPhysics(const worlds::World& world, const RobotOptions& options,
               const SE2& world_from_robot_start);
  ~RobotPhysics();
  RobotPhysics(const RobotPhysics&) = delete;
  RobotPhysics& operator=(const RobotPhysics&) = delete;

  /// Sets the wheel motors' target speeds (rad/s, positive rolls forward), clamped to the motor
  /// limit, until the next call.
  void SetWheelSpeeds(double left_rps, double right_rps);
  /// Advances by one physics step.
  void Step();
  const RobotState& state() const { return state_; }
  /// The chassis' contacts with world objects after the last step (ordered by instance id).
  const std::vector<Contact>& contacts() const { return contacts_; }
  std::uint64_t steps() const { return steps_; }

 private:
  struct Impl;
  void ReadState();
  std::unique_ptr<Impl> impl_;
  RobotState state_;
  std::vector<Contact> contacts_;
  std::uint64_t steps_ = 0;
};

/// Wheel speeds (rad/s, left and right) that drive the nominal robot at `linear_mps`,
/// `angular_rps` (inverse differential-drive kinematics with the nominal geometry).
Eigen::Vector2d WheelSpeedsFor(const RobotOptions& options, double linear_mps, double angular_rps);

}  // namespace corridorsim::sim
