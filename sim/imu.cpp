#include "sim/imu.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/options_checker.h"
#include "sim/sensor_mount.h"

namespace corridorsim::sim {
namespace {

// Bounds of the 3-vector keys, which the table cannot check (a list's length and elements).
constexpr double kMaxGyroscopeBiasRadS = 1.0;     // 57 deg/s: far beyond any MEMS turn-on bias
constexpr double kMaxAccelerometerBiasMS2 = 5.0;  // half a g
constexpr double kMinScale = 0.5, kMaxScale = 2.0;
constexpr double kMaxMisalignmentRad = 0.1;  // small angles: 5.7 deg

// The first problem of a 3-vector key: its length, then each element in [lo, hi] (or (lo, hi)).
std::optional<OptionsProblem> CheckTriple(const std::vector<double>& values, const std::string& key,
                                          double lo, double hi, bool open) {
  if (values.size() != 3) {
    return OptionsProblem{key,
                          "must list 3 values, x y z (got " + std::to_string(values.size()) + ")"};
  }
  for (std::size_t i = 0; i < 3; ++i) {
    const double v = values[i];
    const bool ok = open ? (v > lo && v < hi) : (v >= lo && v <= hi);  // false for NaN
    if (!ok) {
      return OptionsProblem{key, std::string("element ") + "xyz"[i] + " must lie in " +
                                     (open ? "(" : "[") + FormatNumber(lo) + ", " +
                                     FormatNumber(hi) + (open ? ")" : "]") + " (got " +
                                     FormatNumber(v) + ")"};
    }
  }
  return std::nullopt;
}

Eigen::Vector3d Vector(const std::vector<double>& values) {
  return Eigen::Vector3d(values[0], values[1], values[2]);
}

}  // namespace

std::optional<OptionsProblem> ImuOptions::Check() const {
  if (auto problem = CheckOptionBounds(ImuOptionsTable(), *this)) return problem;
  if (!(phase_s * rate_hz < 1.0)) {
    return OptionsProblem{"phase_s",
                          "must lie in [0, 1 / rate_hz) (got " + FormatNumber(phase_s) + " s)"};
  }
  const std::pair<const std::vector<double>*, const char*> biases[] = {
      {&gyroscope_bias_rad_s, "gyroscope_bias_rad_s"},
      {&accelerometer_bias_m_s2, "accelerometer_bias_m_s2"}};
  const double max_bias[] = {kMaxGyroscopeBiasRadS, kMaxAccelerometerBiasMS2};
  for (int i = 0; i < 2; ++i) {
    if (auto p = CheckTriple(*biases[i].first, biases[i].second, -max_bias[i], max_bias[i], false))
      return p;
  }
  if (auto p = CheckTriple(gyroscope_scale, "gyroscope_scale", kMinScale, kMaxScale, true))
    return p;
  if (auto p = CheckTriple(accelerometer_scale, "accelerometer_scale", kMinScale, kMaxScale, true))
    return p;
  if (auto p = CheckTriple(gyroscope_misalignment_rad, "gyroscope_misalignment_rad",
                           -kMaxMisalignmentRad, kMaxMisalignmentRad, true))
    return p;
  if (auto p = CheckTriple(accelerometer_misalignment_rad, "accelerometer_misalignment_rad",
                           -kMaxMisalignmentRad, kMaxMisalignmentRad, true))
    return p;
  return std::nullopt;
}

Eigen::Matrix3d ImuAxesMatrix(const Eigen::Vector3d& misalignment_rad) {
  const double s0 = std::sin(misalignment_rad[0]), c0 = std::cos(misalignment_rad[0]);
  const double s1 = std::sin(misalignment_rad[1]), s2 = std::sin(misalignment_rad[2]);
  Eigen::Matrix3d a;
  a << 1.0, 0.0, 0.0,  //
      s0, c0, 0.0,     //
      s1, s2, std::sqrt(1.0 - s1 * s1 - s2 * s2);
  return a;
}

ImuSample ExactImuSample(const RobotState& previous, const RobotState& current, double dt_s,
                         const SE3& robot_from_imu, TimeNs stamp_ns, const std::string& id) {
  CheckOrDie(dt_s > 0.0, "sim::ExactImuSample", "the physics step must be positive");
  const Eigen::Vector3d lever_arm_in_robot = robot_from_imu.translation();
  // The world-frame velocity of the IMU point: v_R + w x (R_world_robot r).
  auto imu_velocity_in_world = [&](const RobotState& s) -> Eigen::Vector3d {
    return s.linear_velocity_in_world +
           s.angular_velocity_in_world.cross(s.world_from_robot.rotation() * lever_arm_in_robot);
  };
  // The step's acceleration: exact under Bullet's semi-implicit Euler (see the header).
  const Eigen::Vector3d acceleration_in_world =
      (imu_velocity_in_world(current) - imu_velocity_in_world(previous)) / dt_s;
  const Eigen::Matrix3d world_from_imu =
      current.world_from_robot.rotation() * robot_from_imu.rotation();
  ImuSample sample;
  sample.stamp_ns = stamp_ns;
  sample.sensor_id = id;
  sample.angular_velocity_rad_s = world_from_imu.transpose() * current.angular_velocity_in_world;
  sample.linear_acceleration_m_s2 =
      world_from_imu.transpose() *
      (acceleration_in_world + Eigen::Vector3d(0.0, 0.0, kGravityM_S2));
  return sample;
}

ImuModel::Triad ImuModel::MakeTriad(const std::vector<double>& scale,
                                    const std::vector<double>& misalignment, double noise_density,
                                    double random_walk, double range,
                                    const std::vector<double>& bias, bool noise, std::uint64_t seed,
                                    const std::string& stream) {
  Triad t{Vector(scale).asDiagonal() * ImuAxesMatrix(Vector(misalignment)),
          noise_density,
          random_walk,
          range,
          noise ? Vector(bias) : Eigen::Vector3d::Zero(),
          RandomStream(seed, 0, stream),
          RandomStream(seed, 0, stream + "_bias")};
  return t;
}

ImuModel::ImuModel(const ImuOptions& o, std::uint64_t seed)
    : noise_(o.noise),
      period_ns_(PeriodFromRateHz(o.rate_hz)),
      gyroscope_(MakeTriad(o.gyroscope_scale, o.gyroscope_misalignment_rad,
                           o.gyroscope_noise_density, o.gyroscope_random_walk,
                           o.gyroscope_range_rad_s, o.gyroscope_bias_rad_s, o.noise, seed,
                           "sim.imu." + o.id + ".gyroscope")),
      accelerometer_(MakeTriad(o.accelerometer_scale, o.accelerometer_misalignment_rad,
                               o.accelerometer_noise_density, o.accelerometer_random_walk,
                               o.accelerometer_range_m_s2, o.accelerometer_bias_m_s2, o.noise, seed,
                               "sim.imu." + o.id + ".accelerometer")) {
  CheckOrDie(!o.Check(), "sim::ImuModel", "the options must pass Check()");
}

Eigen::Vector3d ImuModel::Apply(Triad& triad, const Eigen::Vector3d& exact, double dt_s) {
  // 1. The bias walks over the interval (Kalibr: b[k] = b[k-1] + sigma_bd w, sigma_bd =
  //    sigma_b sqrt(dt)).
  if (triad.random_walk > 0.0) {
    const double sigma_bd = triad.random_walk * std::sqrt(dt_s);
    for (int i = 0; i < 3; ++i) triad.bias[i] += sigma_bd * triad.bias_rng.Normal();
  }
  // 2. Scale and misalignment on the true value, plus bias and white noise (Kalibr: sigma_d =
  //    sigma / sqrt(dt)).
  Eigen::Vector3d measured = triad.scale_misalignment * exact + triad.bias;
  if (triad.noise_density > 0.0) {
    const double sigma_d = triad.noise_density / std::sqrt(dt_s);
    for (int i = 0; i < 3; ++i) measured[i] += sigma_d * triad.noise_rng.Normal();
  }
  // 3. Saturation, per axis.
  for (int i = 0; i < 3; ++i) measured[i] = std::clamp(measured[i], -triad.range, triad.range);
  return measured;
}

ImuSample ImuModel::Measure(const ImuSample& exact) {
  CheckOrDie(!last_stamp_ns_ || exact.stamp_ns > *last_stamp_ns_, "sim::ImuModel::Measure",
             "sample stamps must increase");
  const TimeNs interval_ns = last_stamp_ns_ ? exact.stamp_ns - *last_stamp_ns_ : period_ns_;
  last_stamp_ns_ = exact.stamp_ns;
  if (!noise_) return exact;
  const double dt_s = static_cast<double>(interval_ns) * 1e-9;
  ImuSample measured = exact;
  measured.angular_velocity_rad_s = Apply(gyroscope_, exact.angular_velocity_rad_s, dt_s);
  measured.linear_acceleration_m_s2 = Apply(accelerometer_, exact.linear_acceleration_m_s2, dt_s);
  return measured;
}

}  // namespace corridorsim::sim
