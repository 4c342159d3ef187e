#pragma once
// The sensors that sample the robot's motion and the world's geometry without rendering: IMUs and
// planar laser scanners (docs/sensors.md). Simulation owns one MotionSensors and asks it, after
// every physics step, for what became due in the step.
//
// An IMU samples at physics step ends only (its period must be a whole number of steps:
// Scenario::CheckSensors refuses another rate), where the state Bullet integrated is exact: the
// acceleration that acted during the step is the velocity change over it (sim/imu.h). A laser
// sweep's beams fire one after another over the sweep (sim/laser_scanner.h); each beam is cast
// from the scanner's pose at its own instant, interpolated between the physics steps around it
// as every other sensor's stamp is (translation linearly, rotation by slerp). A sweep is
// delivered once its last beam has fired.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "common/sensor_messages.h"
#include "common/time.h"
#include "sim/imu.h"
#include "sim/laser_scanner.h"
#include "sim/robot.h"
#include "worlds/world.h"

namespace corridorsim::sim {

/// One IMU sample with its truth.
struct ImuMessage {
  std::size_t imu = 0;                                           // index among the enabled IMUs
  ImuSample sample;                                              // what the IMU reports
  ImuSample exact;                                               // the noise-free sample (truth)
  Eigen::Vector3d gyroscope_bias = Eigen::Vector3d::Zero();      // the true biases in `sample`
  Eigen::Vector3d accelerometer_bias = Eigen::Vector3d::Zero();  // (0 with noise off)
  SE3 world_from_imu;                                            // truth at the stamp
  Eigen::Vector3d velocity_in_world = Eigen::Vector3d::Zero();   // of the IMU's origin, m/s
};

/// One laser sweep with its truth, per beam.
struct ScanMessage {
  std::size_t laser = 0;  // index among the enabled scanners
  LaserScan scan;         // what the scanner reports (stamp_ns: its first beam)
  std::vector<BeamTruth> truth;
  std::vector<SE3> world_from_laser;  // the scanner's pose as each beam fired (truth)
  TimeNs complete_ns = 0;             // its last beam: when it is delivered
};

class MotionSensors {
 public:
  /// The enabled sensors of `imus` and `lasers` (in their order). `step_ns`: the physics step.
  MotionSensors(const worlds::World& world, const std::vector<ImuOptions>& imus,
                const std::vector<LaserOptions>& lasers, std::uint64_t seed, TimeNs step_ns);
  ~MotionSensors();
  MotionSensors(const MotionSensors&) = delete;
  MotionSensors& operator=(const MotionSensors&) = delete;

  /// What became due in the step from `before` to `after` (their stamps and states; `before`
  /// at stamp 0 also serves the sensors' stamp 0), appended in stamp order per sensor.
  void Emit(TimeNs before_ns, const RobotState& before, TimeNs after_ns, const RobotState& after,
            std::vector<ImuMessage>* imu, std::vector<ScanMessage>* scans);

  bool empty() const { return imus_.empty() && lasers_.empty(); }

 private:
  struct Imu;
  struct Laser;
  TimeNs step_ns_;
  std::vector<std::unique_ptr<Imu>> imus_;
  std::vector<std::unique_ptr<Laser>> lasers_;
};

}  // namespace corridorsim::sim
