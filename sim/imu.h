#pragma once
// The IMU: what a perfect inertial unit at its mount reads (ExactImuSample, from the robot's true
// state at the end of a physics step) and the errors of a real one (ImuModel: Kalibr's noise
// model, scale factors, axis misalignment, saturation). Truth and noise are separate stages
// (STYLE item 9): the exact sample is the ground truth, ImuModel::Measure turns it into the
// message a SLAM pipeline gets.

#include <cstdint>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/error.h"
#include "common/options_table.h"
#include "common/pose.h"
#include "common/random.h"
#include "common/sensor_messages.h"
#include "common/time.h"
#include "render/camera_options.h"
#include "sim/robot.h"

namespace corridorsim::sim {

/// The gravity of the simulated world (m/s^2), along -z of the world frame: the physics pulls the
/// robot down with it and an IMU at rest reads it as +g along its up axis. One definition for both.
inline constexpr double kGravityM_S2 = 9.81;

/// One IMU on the robot (a named sensor: the `type` key and the id's map are the caller's).
///
/// Noise defaults: the ADIS16448 of the EuRoC MAV datasets (Burri et al., "The EuRoC micro aerial
/// vehicle datasets", IJRR 2016), in Kalibr's imu.yaml names and units as EuRoC's own Kalibr
/// configuration gives them. Ranges: the same part's datasheet (Analog Devices ADIS16448,
/// +-1000 deg/s and +-18 g, g = 9.80665 m/s^2 as datasheets define it).
struct ImuOptions {
  std::string id;  // the sensor's name (random streams "sim.imu.<id>.*", messages' sensor_id)
  bool enabled = true;
  double rate_hz = 200.0;  // samples per second; the caller samples at physics step ends
  double phase_s = 0.0;    // first sample at this time (s, in [0, 1 / rate_hz)), then every period
  // Where the IMU sits: its body axes (x forward, y left, z up at zero angles; sim/sensor_mount.h).
  // Default: on the Pioneer's top plate (0.237 m), above the axle's midpoint (the robot frame's
  // origin, the centre it turns about in place), level and facing forward.
  render::Mount mount{0.0, 0.0, 0.237, 0.0, 0.0, 0.0};
  bool noise = true;  // false: every error below off, the exact sample

  // Kalibr's continuous-time noise model (Kalibr wiki, "IMU Noise Model"), per axis.
  double gyroscope_noise_density = 1.6968e-04;                    // sigma_g, rad/s/sqrt(Hz)
  double gyroscope_random_walk = 1.9393e-05;                      // sigma_bg, rad/s^2/sqrt(Hz)
  double accelerometer_noise_density = 2.0e-3;                    // sigma_a, m/s^2/sqrt(Hz)
  double accelerometer_random_walk = 3.0e-3;                      // sigma_ba, m/s^3/sqrt(Hz)
  std::vector<double> gyroscope_bias_rad_s = {0.0, 0.0, 0.0};     // initial bias, x y z
  std::vector<double> accelerometer_bias_m_s2 = {0.0, 0.0, 0.0};  // initial bias, x y z
  // Per-axis scale factors (x y z) and non-orthogonal axes (ImuAxesMatrix): the matrix
  // diag(scale) A(misalignment) multiplies the true value.
  std::vector<double> gyroscope_scale = {1.0, 1.0, 1.0};
  std::vector<double> accelerometer_scale = {1.0, 1.0, 1.0};
  std::vector<double> gyroscope_misalignment_rad = {0.0, 0.0, 0.0};
  std::vector<double> accelerometer_misalignment_rad = {0.0, 0.0, 0.0};
  // Saturation: each axis' output is clamped to +-range.
  double gyroscope_range_rad_s = 1000.0 * std::numbers::pi / 180.0;  // 1000 deg/s
  double accelerometer_range_m_s2 = 18.0 * 9.80665;                  // 18 g

  /// The first problem (key relative to the sensor, e.g. "gyroscope_scale"), or nothing.
  std::optional<OptionsProblem> Check() const;
};

/// The keys of one IMU (parsing, bounds, echo, docs); the list keys' lengths and element bounds
/// are ImuOptions::Check()'s.
const OptionTable<ImuOptions>& ImuOptionsTable();

/// The non-orthogonal axis model of three small angles m = (m0, m1, m2): row i of A is the unit
/// vector of sensing axis i in the IMU's (orthogonal) body frame, so axis i reads row_i . v.
///   x axis: (1, 0, 0)                              exactly the body's x
///   y axis: (sin m0, cos m0, 0)                    in the body's xy plane, tilted towards x by m0
///   z axis: (sin m1, sin m2, sqrt(1 - sin^2 m1 - sin^2 m2))   tilted towards x by m1, y by m2
/// A is lower-triangular (the body frame is the one the sensor's x axis and xy plane define), the
/// form of Kalibr's scale-misalignment IMU models and of Tedaldi et al., "A robust and easy to
/// implement method for IMU calibration without external equipments" (ICRA 2014), eq. 1-3.
/// A = I at m = 0.
Eigen::Matrix3d ImuAxesMatrix(const Eigen::Vector3d& misalignment_rad);

/// What a perfect IMU at `robot_from_imu` reads at the end of the physics step that took the robot
/// to `current` from `previous`, the state one physics step before (`dt_s` the step, > 0). The
/// sample is the instantaneous state at the step's end: the caller samples an IMU only at physics
/// step ends (a rate whose period is not a whole number of steps is refused there), so no
/// interpolation happens here.
///
/// Bullet integrates semi-implicitly (velocities first, then positions with the new velocities),
/// so the acceleration that acted during the step is exactly (v_k - v_{k-1}) / dt. With the
/// lever arm r = robot_from_imu's translation, the IMU point moves at
///   v_imu = v_R + w x (R_world_robot r)          (v_R, w: the state's world-frame velocities)
/// and its acceleration a_imu = (v_imu,k - v_imu,k-1) / dt holds the tangential (dw/dt x r) and
/// centripetal (w x (w x r)) terms. With R_world_imu = R_world_robot,k R_robot_imu (ROS
/// sensor_msgs/Imu conventions, specific force):
///   angular velocity    = R_world_imu^T w_k
///   linear acceleration = R_world_imu^T (a_imu + g e_z)   (at rest: +g along the IMU's up axis)
///
/// `previous` may also be an earlier state, n steps before, with dt_s = n steps: the acceleration
/// is then the exact mean over those steps (a boxcar anti-aliasing filter, as an IMU that averages
/// over its sample period), the angular velocity still the instantaneous one. Per step, the
/// contact solver's velocity jitter of a standing robot (about 1e-4 m/s) shows as 0.07 m/s^2 RMS;
/// over a 5 ms period it is half that (tests/sim/imu_test.cpp prints both).
ImuSample ExactImuSample(const RobotState& previous, const RobotState& current, double dt_s,
                         const SE3& robot_from_imu, TimeNs stamp_ns, const std::string& id);

/// A real IMU's errors on exact samples. Per sample, with dt the time since the previous sample
/// (the first: 1 / rate_hz), for the gyroscope and the accelerometer alike (Kalibr's discrete
/// model, "IMU Noise Model" wiki):
///   1. the bias walks: b += sigma_b sqrt(dt) N(0, I)     (so the first sample's bias has walked
///      one period from the configured initial bias)
///   2. y = diag(scale) A(misalignment) x + b + n,  n ~ N(0, sigma^2 / dt I)
///   3. each axis of y is clamped to +-range (saturation)
/// Streams (common/random.h, seed and run 0): the white noise of each from
/// "sim.imu.<id>.gyroscope" and "sim.imu.<id>.accelerometer", the bias walks from
/// "sim.imu.<id>.gyroscope_bias" and "sim.imu.<id>.accelerometer_bias", so switching one source
/// off leaves the others' numbers unchanged; a source whose sigma is 0 draws nothing. With
/// noise: false every error is off: Measure returns the exact sample and the biases are 0.
class ImuModel {
 public:
  /// `options` must pass Check().
  ImuModel(const ImuOptions& options, std::uint64_t seed);

  /// The measurement of `exact`, whose stamp must be later than the previous one's.
  ImuSample Measure(const ImuSample& exact);

  /// The true biases after the last sample (ground truth; 0 with noise off).
  const Eigen::Vector3d& gyroscope_bias() const { return gyroscope_.bias; }
  const Eigen::Vector3d& accelerometer_bias() const { return accelerometer_.bias; }

 private:
  // One triad (the gyroscope or the accelerometer) and its error state.
  struct Triad {
    Eigen::Matrix3d scale_misalignment = Eigen::Matrix3d::Identity();  // diag(scale) A
    double noise_density = 0.0;                                        // sigma
    double random_walk = 0.0;                                          // sigma_b
    double range = 0.0;                                                // clamp, per axis
    Eigen::Vector3d bias = Eigen::Vector3d::Zero();
    RandomStream noise_rng;
    RandomStream bias_rng;
  };
  static Eigen::Vector3d Apply(Triad& triad, const Eigen::Vector3d& exact, double dt_s);
  // A triad from its options; `stream`: its streams' name (`stream`, `stream` + "_bias").
  static Triad MakeTriad(const std::vector<double>& scale, const std::vector<double>& misalignment,
                         double noise_density, double random_walk, double range,
                         const std::vector<double>& bias, bool noise, std::uint64_t seed,
                         const std::string& stream);

  bool noise_;
  TimeNs period_ns_;
  std::optional<TimeNs> last_stamp_ns_;
  Triad gyroscope_;
  Triad accelerometer_;
};

}  // namespace corridorsim::sim
