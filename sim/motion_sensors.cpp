#include "sim/motion_sensors.h"

#include <utility>

#include "common/error.h"
#include "sim/simulation.h"

namespace corridorsim::sim {

struct MotionSensors::Imu {
  Imu(const ImuOptions& o, std::uint64_t seed)
      : options(o),
        robot_from_imu(o.mount.RobotFromBody()),
        model(o, seed),
        clock(PeriodFromRateHz(o.rate_hz), FromSeconds(o.phase_s)) {}
  ImuOptions options;
  SE3 robot_from_imu;
  ImuModel model;
  SensorClock clock;
  // The state at the previous sample (at first the start): the acceleration a sample reports is
  // the exact mean over its period (sim/imu.h, ExactImuSample), as an IMU that averages over it.
  RobotState previous;
  TimeNs previous_ns = 0;
  bool started = false;
};

struct MotionSensors::Laser {
  Laser(const worlds::World& world, const LaserOptions& o, std::uint64_t seed)
      : robot_from_laser(o.mount.RobotFromBody()),
        scanner(world, o, seed),
        clock(scanner.period_ns(), scanner.phase_ns()) {}
  SE3 robot_from_laser;
  LaserScanner scanner;
  SensorClock clock;  // the sweeps' first beams
  // The sweep being fired: its beams so far.
  std::vector<BeamTruth> beams;
  std::vector<SE3> poses;
};

MotionSensors::MotionSensors(const worlds::World& world, const std::vector<ImuOptions>& imus,
                             const std::vector<LaserOptions>& lasers, std::uint64_t seed,
                             TimeNs step_ns)
    : step_ns_(step_ns) {
  for (const ImuOptions& o : imus) {
    if (!o.enabled) continue;
    CheckOrDie(PeriodFromRateHz(o.rate_hz) % step_ns == 0 && FromSeconds(o.phase_s) % step_ns == 0,
               "sim::MotionSensors", "an IMU's period and phase must be whole physics steps");
    imus_.push_back(std::make_unique<Imu>(o, seed));
  }
  for (const LaserOptions& o : lasers) {
    if (o.enabled) lasers_.push_back(std::make_unique<Laser>(world, o, seed));
  }
}

MotionSensors::~MotionSensors() = default;

namespace {

// The pose at `stamp` between two physics steps (the simulation's interpolation of every stamp).
SE3 PoseAt(TimeNs a_ns, const SE3& a, TimeNs b_ns, const SE3& b, TimeNs stamp) {
  if (stamp == b_ns) return b;
  if (stamp == a_ns) return a;
  const double t = static_cast<double>(stamp - a_ns) / static_cast<double>(b_ns - a_ns);
  return SE3::Interpolate(a, b, t);
}

}  // namespace

void MotionSensors::Emit(TimeNs before_ns, const RobotState& before, TimeNs after_ns,
                         const RobotState& after, std::vector<ImuMessage>* imu,
                         std::vector<ScanMessage>* scans) {
  for (std::size_t k = 0; k < imus_.size(); ++k) {
    Imu& s = *imus_[k];
    if (!s.started) {  // the start state, before the first step
      s.previous = before;
      s.previous_ns = before_ns;
      s.started = true;
    }
    while (s.clock.next_ns() <= after_ns) {
      const TimeNs stamp = s.clock.next_ns();
      // Stamp 0 (the first step's start): the robot stands still; else a step end.
      const bool start = stamp == before_ns;
      const RobotState& state = start ? before : after;
      ImuMessage m;
      m.imu = k;
      // Over the period since the previous sample (none at the start: no velocity change).
      const double dt_s = start ? ToSeconds(step_ns_) : ToSeconds(stamp - s.previous_ns);
      m.exact = ExactImuSample(s.previous, state, dt_s, s.robot_from_imu, stamp, s.options.id);
      s.previous = state;
      s.previous_ns = stamp;
      m.sample = s.model.Measure(m.exact);
      m.gyroscope_bias = s.model.gyroscope_bias();
      m.accelerometer_bias = s.model.accelerometer_bias();
      m.world_from_imu = state.world_from_robot * s.robot_from_imu;
      const Eigen::Vector3d lever =
          state.world_from_robot.rotation() * s.robot_from_imu.translation();
      m.velocity_in_world =
          state.linear_velocity_in_world + state.angular_velocity_in_world.cross(lever);
      imu->push_back(std::move(m));
      s.clock.Advance();
    }
  }
  for (std::size_t k = 0; k < lasers_.size(); ++k) {
    Laser& s = *lasers_[k];
    const LaserScanner& scanner = s.scanner;
    const int beams = scanner.beam_count();
    while (true) {
      const int i = static_cast<int>(s.beams.size());
      const TimeNs beam_ns = s.clock.next_ns() + i * scanner.time_increment_ns();
      if (beam_ns > after_ns) break;
      if (i == 0) {  // a new sweep (the last one's vectors went out with its message)
        s.beams.reserve(static_cast<std::size_t>(beams));
        s.poses.reserve(static_cast<std::size_t>(beams));
      }
      const SE3 world_from_laser =
          PoseAt(before_ns, before.world_from_robot, after_ns, after.world_from_robot, beam_ns) *
          s.robot_from_laser;
      s.beams.push_back(scanner.Cast(i, world_from_laser));
      s.poses.push_back(world_from_laser);
      if (i + 1 < beams) continue;
      ScanMessage m;
      m.laser = k;
      m.scan = scanner.Measure(s.clock.next_ns(), s.clock.count(), s.beams);
      m.truth = std::move(s.beams);
      m.world_from_laser = std::move(s.poses);
      m.complete_ns = beam_ns;
      scans->push_back(std::move(m));
      s.beams.clear();
      s.poses.clear();
      s.clock.Advance();
    }
  }
}

}  // namespace corridorsim::sim
