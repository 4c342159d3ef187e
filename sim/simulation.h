#pragma once
// The closed simulation loop: fixed-step physics, the path follower driving from ground truth,
// and the sensor clock that emits the messages due at each step (odometry, camera frames rendered
// at the true pose at their stamp) together with the ground truth of every instant.
//
// Time is int64 nanoseconds: physics step k ends at k * step_ns; a sensor with period T and
// phase p is stamped at p + n T exactly. A stamp that falls between two physics steps takes the
// state interpolated between them (wheel angles linearly, the pose by slerp), so stamps never
// snap to the physics grid. The truth is reported the same way: at every point of the truth grid
// (n / truth_rate_hz) and every odometry stamp, whatever the physics rate.

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/pose.h"
#include "common/random.h"
#include "common/sensor_messages.h"
#include "common/time.h"
#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "sim/motion_sensors.h"
#include "sim/odometry.h"
#include "sim/robot.h"
#include "sim/robot_path.h"
#include "worlds/world.h"

namespace corridorsim::sim {

/// Stamps phase + n * period, n = 0, 1, ...
class SensorClock {
 public:
  SensorClock(TimeNs period_ns, TimeNs phase_ns) : period_ns_(period_ns), phase_ns_(phase_ns) {}
  TimeNs next_ns() const { return phase_ns_ + count_ * period_ns_; }
  std::uint64_t count() const { return static_cast<std::uint64_t>(count_); }
  void Advance() { ++count_; }

 private:
  TimeNs period_ns_;
  TimeNs phase_ns_;
  std::int64_t count_ = 0;
};

/// Ground truth of one instant.
struct TruthSample {
  TimeNs stamp_ns = 0;
  SE2 world_from_robot_2d;  // the planar pose (x, y, yaw of the robot's x axis)
  RobotState state;         // full 3D pose, velocities, wheel angles
  // world_from_camera of every enabled camera of the rig options (its order), if one was given
  std::vector<SE3> world_from_camera;
};

/// One camera frame with its truth. The rendered images exist only when the simulation renders.
struct CameraMessage {
  TimeNs stamp_ns = 0;
  std::uint64_t frame_index = 0;  // n of the camera's clock: seeds its noise
  std::size_t camera = 0;         // index in the rig's enabled cameras
  SE3 world_from_robot;           // truth at the stamp
  render::CameraFrame frame;      // images (exact depth, noisy depth, labels), world_from_camera
  render::FrameTruth truth;       // the landmarks the camera sees
};

enum class EventKind {
  kCollisionBegin,  // the chassis touches a world object
  kCollisionEnd,
  kSlip,          // an odometry slip event (sim/odometry.h)
  kPathDone,      // the follower reached the path's end
  kTimeout,       // the run's duration ended before the path did
  kFrameDropped,  // a camera frame due at this stamp was lost (sensors.<camera>.drop_probability)
};
std::string EventKindName(EventKind kind);

struct Event {
  TimeNs stamp_ns = 0;
  EventKind kind = EventKind::kPathDone;
  int instance_id = 0;  // collisions: the World object
  worlds::SemanticClass semantic_class = worlds::SemanticClass::kUnknown;
  Eigen::Vector3d position_in_world = Eigen::Vector3d::Zero();  // collisions: contact point
  double depth_m = 0.0;     // collisions: penetration at the first contact
  bool left_wheel = false;  // slips
  double distance_m = 0.0;  // slips: extra distance the wheel reported
  std::string camera_id;    // dropped frames: the camera
};

struct SimulationOptions {
  RobotOptions robot;
  RobotPathOptions robot_path;
  std::uint64_t seed = 1;
  TimeNs max_duration_ns = 0;    // 0: until the path is done (with a safety timeout, see below)
  double truth_rate_hz = 100.0;  // the truth grid: StepOutput::truth_samples at n / rate (Hz)
  // The sensors that need no rendering (sim/motion_sensors.h); the disabled ones are left out.
  std::vector<ImuOptions> imus;
  std::vector<LaserOptions> lasers;
};

/// What became due during one Step(), in stamp order per kind.
struct StepOutput {
  TruthSample truth;  // at the end of the step
  // The truth at every truth-grid stamp and every odometry stamp inside the step (after its
  // start, up to its end; the truth at 0 is Simulation::truth() before the first step), each
  // stamp once, interpolated between the physics steps around it.
  std::vector<TruthSample> truth_samples;
  std::vector<WheelOdometry> odometry;
  std::vector<CameraMessage> frames;
  std::vector<ImuMessage> imu;     // per IMU in stamp order, the IMUs one after another
  std::vector<ScanMessage> scans;  // the sweeps whose last beam fired in the step
  std::vector<Event> events;
};

class Simulation {
 public:
  /// Drives `path` (BuildRobotPath of options.robot_path in `world`). With `rig_options`, the truth
  /// carries every enabled camera's pose; `rig` (optional, built from `rig_options`) renders the
  /// cameras at their rates; without it no camera messages are emitted. The world and rig must
  /// outlive the simulation.
  Simulation(const worlds::World& world, const SimulationOptions& options, RobotPath path,
             render::Rig* rig = nullptr, const render::RigOptions* rig_options = nullptr);
  ~Simulation();

  /// Advances one physics step and returns what became due.
  const StepOutput& Step();
  /// The run is over: the path is done (without a set duration) or the duration has passed.
  bool finished() const { return finished_; }
  /// The follower reached the end of the path.
  bool path_done() const { return path_done_; }
  TimeNs now_ns() const { return now_ns_; }
  const TruthSample& truth() const { return output_.truth; }
  const RobotPath& path() const { return path_; }
  double progress() const;
  /// Wall-clock seconds spent rendering camera frames and computing their truth (for the
  /// run's cost split; never part of an output that must be deterministic).
  /// How often the driver has acted (control_rate_hz times per simulated second, on average).
  std::int64_t control_updates() const { return control_updates_; }
  double render_seconds() const { return render_seconds_; }

 private:
  TruthSample Interpolate(const TruthSample& a, const TruthSample& b, TimeNs stamp) const;
  void EmitDue(const TruthSample& before, const TruthSample& after);
  void TrackContacts();
  void FillTruth(TruthSample* sample) const;  // planar pose and camera poses from the state

  const worlds::World& world_;
  SimulationOptions options_;
  render::Rig* rig_;
  std::vector<render::CameraOptions>
      camera_options_;  // the rig options's enabled cameras, in order
  RobotPath path_;
  std::unique_ptr<PathFollower> follower_;
  std::unique_ptr<RobotPhysics> physics_;
  WheelOdometer odometer_;
  SensorClock odometry_clock_;
  SensorClock truth_clock_;  // the truth grid (SimulationOptions::truth_rate_hz)
  std::vector<SensorClock> camera_clocks_;
  std::vector<RandomStream> drop_rngs_;            // per camera: "sim.clock.drop.<camera>"
  std::unique_ptr<MotionSensors> motion_sensors_;  // IMUs and laser scanners
  TimeNs step_ns_ = 0;
  // The driver's clock: it acts at the first physics step at or after each of its stamps
  // (n / control_rate_hz), so it runs at control_rate_hz on average whatever the physics rate.
  SensorClock control_clock_{1, 0};
  std::int64_t control_updates_ = 0;
  TimeNs now_ns_ = 0;
  TimeNs end_ns_ = 0;
  bool finished_ = false;
  bool path_done_ = false;
  double render_seconds_ = 0.0;
  std::vector<Contact> touching_;  // contacts after the previous step
  StepOutput output_;
};

/// TUM trajectory line: "t x y z qx qy qz qw" (seconds, metres), fixed precision.
std::string TumLine(TimeNs stamp_ns, const SE3& pose);

}  // namespace corridorsim::sim
