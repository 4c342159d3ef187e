// Tests sim/imu.cpp: the exact IMU against quantities the IMU code does not compute (the physics'
// own heading, gravity and the centripetal acceleration of a known turn), the noise model against
// an independent Allan deviation, and the deterministic error terms (scale, misalignment, bias,
// saturation), the streams and the options' checks.
#include "sim/imu.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/generated_worlds.h"
#include "worlds/world.h"

namespace corridorsim::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A 12 m straight corridor, 2.4 m wide (walls at y = +-1.2), without doors or furniture.
const worlds::World& Corridor() {
  static const worlds::World world = worlds::Generate(test::BareCorridorOptions(12.0), 3);
  return world;
}

double Yaw(const SE3& pose) {
  const Eigen::Vector3d x = pose.rotation().col(0);
  return std::atan2(x.y(), x.x());
}

// A level IMU at (x, y, z) in the robot frame with the given heading and elevation and roll.
SE3 MountAt(double x, double y, double z, double yaw_deg = 0, double pitch_deg = 0,
            double roll_deg = 0) {
  return render::Mount{x, y, z, yaw_deg, pitch_deg, roll_deg}.RobotFromBody();
}

// Options whose every error is off but noise stays on (the error terms a test switches on alone).
ImuOptions Quiet() {
  ImuOptions o;
  o.id = "test";
  o.gyroscope_noise_density = o.gyroscope_random_walk = 0;
  o.accelerometer_noise_density = o.accelerometer_random_walk = 0;
  return o;
}

ImuSample Sample(TimeNs stamp_ns, const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel) {
  ImuSample s;
  s.stamp_ns = stamp_ns;
  s.sensor_id = "test";
  s.angular_velocity_rad_s = gyro;
  s.linear_acceleration_m_s2 = accel;
  return s;
}

// Drives a script of (duration, linear, angular) legs, each command ramped from the previous one
// over 0.4 s (a step change tips the Pioneer on its caster), and calls visit(previous, current)
// after every physics step. No leg brings the robot near a wall.
template <class Visit>
void DriveScript(const RobotOptions& options, RobotPhysics& robot, Visit visit) {
  struct Leg {
    double seconds, linear_mps, angular_rps;
  };
  // Speed-ups, arcs both ways, spins in place both ways, a stop: 11 s.
  const Leg legs[] = {{1.5, 0.5, 0.0},  {2.0, 0.4, 0.8}, {2.0, 0.0, -2.0},
                      {2.0, 0.3, -0.6}, {1.5, 0.0, 1.5}, {2.0, 0.0, 0.0}};
  const double dt_s = static_cast<double>(options.physics_step_ns()) * 1e-9;
  double linear = 0.0, angular = 0.0;
  for (const Leg& leg : legs) {
    const double from_linear = linear, from_angular = angular;
    const auto steps = static_cast<int>(std::lround(leg.seconds / dt_s));
    for (int i = 0; i < steps; ++i) {
      const double ramp = std::min(1.0, (i + 1) * dt_s / 0.4);
      linear = from_linear + ramp * (leg.linear_mps - from_linear);
      angular = from_angular + ramp * (leg.angular_rps - from_angular);
      const Eigen::Vector2d wheels = WheelSpeedsFor(options, linear, angular);
      robot.SetWheelSpeeds(wheels.x(), wheels.y());
      const RobotState previous = robot.state();
      robot.Step();
      visit(previous, robot.state());
    }
  }
}

TEST_CASE(
    "the integrated gyroscope follows the physics' true heading and orientation through "
    "turns and accelerations",
    "[imu]") {
  RobotOptions options;
  RobotPhysics robot(Corridor(), options, SE2(3.0, 0.0, 0.2));
  for (int i = 0; i < 500; ++i) robot.Step();  // settle on the floor
  const double dt_s = static_cast<double>(options.physics_step_ns()) * 1e-9;
  // A level IMU, yawed and off-centre: its z gyroscope reads the yaw rate. A tilted one
  // (yaw 30, pitch 20, roll -40 deg): its three axes integrate to its orientation.
  const SE3 level = MountAt(0.12, -0.05, 0.237, 30.0);
  const SE3 tilted = MountAt(-0.1, 0.08, 0.2, 30.0, 20.0, -40.0);
  double heading = Yaw(robot.state().world_from_robot);
  // Orientation of the tilted IMU integrated from its gyroscope, body frame: R <- R exp(w dt).
  Eigen::Matrix3d world_from_tilted = robot.state().world_from_robot.rotation() * tilted.rotation();
  double worst_heading = 0.0, worst_orientation = 0.0, max_rate = 0.0, turned = 0.0;
  std::size_t contacts = 0;
  TimeNs stamp_ns = 0;
  DriveScript(options, robot, [&](const RobotState& previous, const RobotState& current) {
    stamp_ns += options.physics_step_ns();
    const ImuSample s = ExactImuSample(previous, current, dt_s, level, stamp_ns, "level");
    CHECK(s.stamp_ns == stamp_ns);
    CHECK(s.sensor_id == "level");
    heading += s.angular_velocity_rad_s.z() * dt_s;
    worst_heading =
        std::max(worst_heading, std::abs(NormalizeAngle(heading - Yaw(current.world_from_robot))));
    max_rate = std::max(max_rate, std::abs(s.angular_velocity_rad_s.z()));
    turned += std::abs(s.angular_velocity_rad_s.z()) * dt_s;

    const ImuSample t = ExactImuSample(previous, current, dt_s, tilted, stamp_ns, "tilted");
    const Eigen::Vector3d rotation_vector = t.angular_velocity_rad_s * dt_s;
    world_from_tilted =
        world_from_tilted *
        Eigen::AngleAxisd(rotation_vector.norm(), rotation_vector.normalized()).toRotationMatrix();
    const Eigen::Matrix3d truth = current.world_from_robot.rotation() * tilted.rotation();
    worst_orientation = std::max(worst_orientation,
                                 Eigen::AngleAxisd(truth.transpose() * world_from_tilted).angle());
    contacts += robot.contacts().size();
  });
  std::printf(
      "imu: over %.1f rad turned (up to %.2f rad/s): worst heading error %.3g rad "
      "(integrated z gyroscope), worst orientation error %.3g rad (3 axes)\n",
      turned, max_rate, worst_heading, worst_orientation);
  CHECK(contacts == 0);
  CHECK(max_rate > 1.9);  // the spins happened
  CHECK(turned > 8.0);
  CHECK(worst_heading < 1e-8);
  CHECK(worst_orientation < 1e-11);
}

TEST_CASE(
    "at rest the accelerometer reads +g on its up axis, rotated with a pitched or rolled "
    "mount",
    "[imu]") {
  RobotOptions options;
  RobotPhysics robot(Corridor(), options, SE2(4.0, 0.2, 0.7));
  const double dt_s = static_cast<double>(options.physics_step_ns()) * 1e-9;
  for (int i = 0; i < 2000; ++i) robot.Step();  // settle
  const double g = kGravityM_S2;
  const double s30 = std::sin(30 * kDeg), c30 = std::cos(30 * kDeg);
  const double s45 = std::sin(45 * kDeg);
  struct Case {
    SE3 robot_from_imu;
    Eigen::Vector3d expected_accel;
  };
  // Expected values from the mount's angles alone: the up direction in the IMU's axes.
  const Case cases[] = {
      {MountAt(0.0, 0.0, 0.237), {0, 0, g}},
      {MountAt(0.1, 0.1, 0.2, 90.0), {0, 0, g}},                          // yaw changes nothing
      {MountAt(0.0, 0.0, 0.237, 0.0, 30.0), {g * s30, 0, g * c30}},       // x tilted up 30 deg
      {MountAt(0.0, 0.0, 0.237, 0.0, 0.0, 45.0), {0, g * s45, g * s45}},  // rolled: y rises
      {MountAt(0.0, 0.0, 0.237, 0.0, 0.0, 180.0), {0, 0, -g}},            // upside down
      {MountAt(0.0, 0.0, 0.237, 0.0, 90.0), {g, 0, 0}},                   // x straight up
  };
  // Per physics step (previous = one step before) and per 5 ms IMU period (previous = 5 steps
  // before, dt = 5 ms: the mean specific force over the period).
  const int n = 1000, period_steps = 5;
  std::vector<RobotState> states{robot.state()};
  for (int i = 0; i < n; ++i) {
    robot.Step();
    states.push_back(robot.state());
  }
  double worst_step = 0.0, worst_period = 0.0, worst_mean = 0.0, worst_gyro = 0.0;
  double square_step = 0.0, square_period = 0.0;  // of the level mount, for the RMS
  for (const Case& c : cases) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 1; k <= n; ++k) {
      const ImuSample s = ExactImuSample(states[k - 1], states[k], dt_s, c.robot_from_imu, 0, "");
      const double error = (s.linear_acceleration_m_s2 - c.expected_accel).norm();
      worst_step = std::max(worst_step, error);
      if (&c == &cases[0]) square_step += error * error;
      worst_gyro = std::max(worst_gyro, s.angular_velocity_rad_s.norm());
      sum += s.linear_acceleration_m_s2;
      if (k % period_steps == 0) {
        const ImuSample p = ExactImuSample(states[k - period_steps], states[k], period_steps * dt_s,
                                           c.robot_from_imu, 0, "");
        const double period_error = (p.linear_acceleration_m_s2 - c.expected_accel).norm();
        worst_period = std::max(worst_period, period_error);
        if (&c == &cases[0]) square_period += period_error * period_error;
      }
    }
    worst_mean = std::max(worst_mean, (sum / n - c.expected_accel).norm());
  }
  std::printf(
      "imu: at rest, accelerometer error (worst, RMS): per step %.3g, %.3g m/s^2; per 5 "
      "ms period %.3g, %.3g; worst of the 1 s means %.3g; worst gyroscope %.3g rad/s\n",
      worst_step, std::sqrt(square_step / n), worst_period,
      std::sqrt(square_period / (n / period_steps)), worst_mean, worst_gyro);
  // The mean over 1 s: the standing robot's tilt and sag alone (1e-3 m/s^2: 0.006 deg).
  CHECK(worst_mean < 1e-3);
  // Single samples carry the contact solver's velocity jitter (about 1e-4 m/s per step),
  // divided by the interval the acceleration is taken over.
  CHECK(worst_step < 0.5);
  CHECK(worst_period < 0.2);
  CHECK(worst_gyro < 5e-3);
}

TEST_CASE(
    "an IMU with a lever arm on a robot turning in place reads the centripetal acceleration "
    "w^2 r towards the centre",
    "[imu]") {
  RobotOptions options;
  RobotPhysics robot(Corridor(), options, SE2(5.0, 0.0, 0.0));
  const double dt_s = static_cast<double>(options.physics_step_ns()) * 1e-9;
  const double r = 0.3;  // m, ahead of and behind the robot frame's origin
  const SE3 front = MountAt(r, 0.0, 0.237), back = MountAt(-r, 0.0, 0.237);
  // On the left, facing left: the centre lies along its -x.
  const SE3 side = MountAt(0.0, r, 0.237, 90.0);
  const Eigen::Vector2d wheels = WheelSpeedsFor(options, 0.0, 2.0);
  robot.SetWheelSpeeds(wheels.x(), wheels.y());
  // The spin-up: the tangential acceleration dw/dt r, to the front IMU's left and the back one's
  // right. Integrated over the spin-up their difference is 2 r (w_end - w_start).
  const double w_start = robot.state().angular_velocity_in_world.z();
  double tangential = 0.0;
  for (int i = 0; i < 1500; ++i) {
    const RobotState previous = robot.state();
    robot.Step();
    const ImuSample f = ExactImuSample(previous, robot.state(), dt_s, front, 0, "front");
    const ImuSample b = ExactImuSample(previous, robot.state(), dt_s, back, 0, "back");
    tangential += (f.linear_acceleration_m_s2.y() - b.linear_acceleration_m_s2.y()) * dt_s;
  }
  const double w_end = robot.state().angular_velocity_in_world.z();
  CHECK(tangential == Approx(2 * r * (w_end - w_start)).epsilon(0.01));
  // At the constant rate: the centripetal acceleration.
  double sum_front_x = 0, sum_back_x = 0, sum_side_x = 0, sum_front_y = 0, sum_w2 = 0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const RobotState previous = robot.state();
    robot.Step();
    const RobotState& current = robot.state();
    const ImuSample f = ExactImuSample(previous, current, dt_s, front, 0, "front");
    const ImuSample b = ExactImuSample(previous, current, dt_s, back, 0, "back");
    const ImuSample l = ExactImuSample(previous, current, dt_s, side, 0, "side");
    sum_front_x += f.linear_acceleration_m_s2.x();
    sum_back_x += b.linear_acceleration_m_s2.x();
    sum_side_x += l.linear_acceleration_m_s2.x();
    sum_front_y += f.linear_acceleration_m_s2.y();
    // w from the physics' state, not the IMU.
    sum_w2 += std::pow(current.angular_velocity_in_world.z(), 2);
  }
  const double w2 = sum_w2 / n;
  const double front_x = sum_front_x / n, back_x = sum_back_x / n, side_x = sum_side_x / n;
  const double front_y = sum_front_y / n;
  std::printf(
      "imu: turning at %.4f rad/s: front x %.5f, back x %.5f, side x %.5f m/s^2 (w^2 r = "
      "%.5f); spin-up: integrated tangential difference %.5f m/s (2 r dw = %.5f)\n",
      std::sqrt(w2), front_x, back_x, side_x, w2 * r, tangential, 2 * r * (w_end - w_start));
  CHECK(std::sqrt(w2) == Approx(2.0).epsilon(0.03));
  // Towards the centre: the front IMU's -x, the back IMU's +x (its x still points forward).
  CHECK(front_x == Approx(-w2 * r).epsilon(0.02));
  CHECK(back_x == Approx(w2 * r).epsilon(0.02));
  CHECK(side_x == Approx(-w2 * r).epsilon(0.02));
  // The difference cancels whatever the origin itself does: 2 w^2 r.
  CHECK(back_x - front_x == Approx(2 * w2 * r).epsilon(0.005));
  CHECK(std::abs(front_y) < 0.01);  // constant rate: no tangential acceleration
}

// Non-overlapping Allan deviation (IEEE Std 952-1997, annex C) of `y` (one value per period
// dt_s) at clusters of m samples, from the cluster means ybar_k:
// AVAR(tau = m dt) = 1 / (2 (K - 1)) sum_k (ybar_{k+1} - ybar_k)^2, K = floor(n / m) clusters.
double AllanVariance(const std::vector<double>& y, std::size_t m) {
  const std::size_t clusters = y.size() / m;
  std::vector<double> means(clusters, 0.0);
  for (std::size_t k = 0; k < clusters; ++k) {
    for (std::size_t j = 0; j < m; ++j) means[k] += y[k * m + j];
    means[k] /= static_cast<double>(m);
  }
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < clusters; ++k) sum += std::pow(means[k + 1] - means[k], 2);
  return sum / (2.0 * static_cast<double>(clusters - 1));
}

TEST_CASE(
    "Allan deviation of a stationary recording recovers the noise densities and random "
    "walks",
    "[imu]") {
  // 100 Hz for 2 h at rest. Densities N and walks K put the crossing of the -1/2 line N /
  // sqrt(tau) and the +1/2 line K sqrt(tau / 3) at tau_c = sqrt(3) N / K = 0.69 s: the white
  // region is read at tau = 0.01 and 0.02 s, the walk's at tau = 10 and 30 s.
  ImuOptions options;
  options.id = "allan";
  options.rate_hz = 100.0;
  options.gyroscope_noise_density = 2e-3;
  options.gyroscope_random_walk = 5e-3;
  options.accelerometer_noise_density = 2e-2;
  options.accelerometer_random_walk = 5e-2;
  REQUIRE_FALSE(options.Check());
  ImuModel model(options, 11);
  const std::size_t n = 100 * 3600 * 2;
  const TimeNs period_ns = PeriodFromRateHz(options.rate_hz);
  const Eigen::Vector3d gravity(0, 0, kGravityM_S2);
  std::vector<double> axes[6];  // gyroscope x y z, accelerometer x y z
  for (auto& a : axes) a.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ImuSample m = model.Measure(
        Sample(static_cast<TimeNs>(i + 1) * period_ns, Eigen::Vector3d::Zero(), gravity));
    for (int k = 0; k < 3; ++k) {
      axes[k].push_back(m.angular_velocity_rad_s[k]);
      axes[3 + k].push_back(m.linear_acceleration_m_s2[k]);
    }
  }
  const double dt = 0.01;
  // The estimator's own spread: over K clusters the K - 1 differences of cluster means are
  // correlated with their neighbours by rho_1 = -1/2 (white noise) or +1/4 (a random walk, the
  // triangle kernels of two differences overlapping by a third), so Var(AVAR) / AVAR^2 =
  // 2 (1 + 2 rho_1^2) / (K - 1): 3 / (K - 1) and 2.25 / (K - 1), and the deviation's relative
  // standard deviation is half the square root. The three axes are independent: their mean AVAR
  // has a third of the variance. Tolerance: 4 of those standard deviations.
  auto tolerance = [&](std::size_t m, double rho_1) {
    const double k = static_cast<double>(n / m);
    return 4.0 * 0.5 * std::sqrt(2.0 * (1.0 + 2.0 * rho_1 * rho_1) / (k - 1.0) / 3.0);
  };
  struct Sensor {
    const char* name;
    int first_axis;
    double density, walk;
  };
  const Sensor sensors[] = {
      {"gyroscope", 0, options.gyroscope_noise_density, options.gyroscope_random_walk},
      {"accelerometer", 3, options.accelerometer_noise_density, options.accelerometer_random_walk}};
  for (const Sensor& s : sensors) {
    auto adev = [&](std::size_t m) {
      double sum = 0;
      for (int k = 0; k < 3; ++k) sum += AllanVariance(axes[s.first_axis + k], m);
      return std::sqrt(sum / 3.0);
    };
    // -1/2 slope: N = sigma(tau) sqrt(tau). At tau = 0.02 s the walk adds K^2 tau^2 / (3 N^2) =
    // 8e-4 to the variance, 0.04 % to the deviation: a tenth of the tolerance.
    for (const std::size_t m : {1, 2}) {
      const double tau = dt * static_cast<double>(m);
      const double estimate = adev(m) * std::sqrt(tau);
      const double tol = tolerance(m, -0.5);
      std::printf(
          "imu: %s noise density at tau %.2f s: %.5g (configured %.5g, tolerance %.2f %%)\n",
          s.name, tau, estimate, s.density, 100 * tol);
      CHECK(estimate == Approx(s.density).epsilon(tol));
    }
    // +1/2 slope: K = sigma(tau) sqrt(3 / tau). At tau = 10 s white noise adds (tau_c / tau)^2 =
    // 0.5 % to the variance, 0.24 % to the deviation: well inside the tolerance (about 6.5 %).
    for (const std::size_t m : {1000, 3000}) {
      const double tau = dt * static_cast<double>(m);
      const double estimate = adev(m) * std::sqrt(3.0 / tau);
      const double tol = tolerance(m, 0.25);
      std::printf("imu: %s random walk at tau %.0f s: %.5g (configured %.5g, tolerance %.1f %%)\n",
                  s.name, tau, estimate, s.walk, 100 * tol);
      CHECK(estimate == Approx(s.walk).epsilon(tol));
    }
  }
  // The true bias the model reports is the walk it added: the mean of the last second sits near
  // it, within 4 standard deviations of that mean's white noise (N^2 / T) and of the walk's own
  // wander over the second (K^2 T / 3), while the walk has wandered K sqrt(7200 s) = 0.4 rad/s.
  const double window_s = 1.0;
  const auto window = static_cast<std::size_t>(window_s / dt);
  double recent = 0;
  for (std::size_t i = n - window; i < n; ++i) recent += axes[0][i];
  const double spread = std::sqrt(std::pow(options.gyroscope_noise_density, 2) / window_s +
                                  std::pow(options.gyroscope_random_walk, 2) * window_s / 3.0);
  CHECK(recent / static_cast<double>(window) ==
        Approx(model.gyroscope_bias().x()).margin(4 * spread));
}

TEST_CASE("each axis saturates at its range", "[imu]") {
  ImuOptions options = Quiet();
  options.gyroscope_range_rad_s = 10.0;
  options.accelerometer_range_m_s2 = 100.0;
  ImuModel model(options, 1);
  const ImuSample m = model.Measure(Sample(5000000, {50.0, -50.0, 1.0}, {200.0, -3.0, -150.0}));
  CHECK(m.angular_velocity_rad_s == Eigen::Vector3d(10.0, -10.0, 1.0));
  CHECK(m.linear_acceleration_m_s2 == Eigen::Vector3d(100.0, -3.0, -100.0));
}

TEST_CASE("scale factors, misalignment and initial biases apply as documented", "[imu]") {
  ImuOptions options = Quiet();
  options.gyroscope_scale = {1.1, 0.9, 1.02};
  options.gyroscope_misalignment_rad = {0.01, -0.02, 0.03};
  options.gyroscope_bias_rad_s = {0.001, -0.002, 0.003};
  options.accelerometer_scale = {0.95, 1.05, 1.0};
  options.accelerometer_misalignment_rad = {-0.05, 0.04, 0.0};
  options.accelerometer_bias_m_s2 = {0.1, 0.0, -0.2};
  REQUIRE_FALSE(options.Check());
  ImuModel model(options, 1);
  // The sensing axes' unit vectors of the header's model, written out here.
  auto axes = [](const std::vector<double>& m) {
    const double s0 = std::sin(m[0]), s1 = std::sin(m[1]), s2 = std::sin(m[2]);
    Eigen::Matrix3d a;
    a.row(0) << 1, 0, 0;
    a.row(1) << s0, std::cos(m[0]), 0;
    a.row(2) << s1, s2, std::sqrt(1 - s1 * s1 - s2 * s2);
    return a;
  };
  const Eigen::Matrix3d gyro_axes = axes(options.gyroscope_misalignment_rad);
  const Eigen::Matrix3d accel_axes = axes(options.accelerometer_misalignment_rad);
  for (int i = 0; i < 3; ++i) CHECK(gyro_axes.row(i).norm() == Approx(1.0));
  CHECK(ImuAxesMatrix(Eigen::Vector3d(0.01, -0.02, 0.03)).isApprox(gyro_axes, 1e-15));
  CHECK(ImuAxesMatrix(Eigen::Vector3d::Zero()) == Eigen::Matrix3d::Identity());
  const Eigen::Vector3d gyro_bias(0.001, -0.002, 0.003), accel_bias(0.1, 0.0, -0.2);
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
    const ImuSample m = model.Measure(Sample(5000000 * (k + 1), 2.0 * e, -3.0 * e));
    for (int i = 0; i < 3; ++i) {
      const double gyro_scale = options.gyroscope_scale[static_cast<std::size_t>(i)];
      const double accel_scale = options.accelerometer_scale[static_cast<std::size_t>(i)];
      CHECK(m.angular_velocity_rad_s[i] ==
            Approx(gyro_scale * gyro_axes(i, k) * 2.0 + gyro_bias[i]).margin(1e-12));
      CHECK(m.linear_acceleration_m_s2[i] ==
            Approx(accel_scale * accel_axes(i, k) * -3.0 + accel_bias[i]).margin(1e-12));
    }
  }
  CHECK(model.gyroscope_bias() == gyro_bias);
  CHECK(model.accelerometer_bias() == accel_bias);
}

TEST_CASE("noise off gives the exact sample and zero biases", "[imu]") {
  ImuOptions options;
  options.id = "exact";
  options.noise = false;
  options.gyroscope_noise_density = 0.05;
  options.accelerometer_random_walk = 0.5;
  options.gyroscope_scale = {1.5, 1.5, 1.5};
  options.accelerometer_bias_m_s2 = {1.0, 1.0, 1.0};
  options.gyroscope_range_rad_s = 0.1;
  ImuModel model(options, 3);
  for (int i = 1; i <= 100; ++i) {
    const ImuSample exact = Sample(i * 5000000, {0.3 * i, -1.0, 2.0}, {0.1, 0.2, 9.81 + i});
    const ImuSample m = model.Measure(exact);
    CHECK(m.stamp_ns == exact.stamp_ns);
    CHECK(m.sensor_id == exact.sensor_id);
    CHECK(m.angular_velocity_rad_s == exact.angular_velocity_rad_s);
    CHECK(m.linear_acceleration_m_s2 == exact.linear_acceleration_m_s2);
  }
  CHECK(model.gyroscope_bias() == Eigen::Vector3d::Zero());
  CHECK(model.accelerometer_bias() == Eigen::Vector3d::Zero());
}

TEST_CASE("the same seed and id give identical samples; another id or seed other noise", "[imu]") {
  auto record = [](const std::string& id, std::uint64_t seed) {
    ImuOptions options;
    options.id = id;
    ImuModel model(options, seed);
    std::vector<double> values;
    for (int i = 1; i <= 50; ++i) {
      const ImuSample m = model.Measure(Sample(i * 5000000, {0.1, 0.0, 0.2}, {0.0, 0.0, 9.81}));
      for (int k = 0; k < 3; ++k) {
        values.push_back(m.angular_velocity_rad_s[k]);
        values.push_back(m.linear_acceleration_m_s2[k]);
      }
    }
    values.push_back(model.gyroscope_bias().x());
    values.push_back(model.accelerometer_bias().z());
    return values;
  };
  const std::vector<double> a = record("imu", 7);
  CHECK(a == record("imu", 7));
  const std::vector<double> other_id = record("imu2", 7), other_seed = record("imu", 8);
  for (std::size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i] != other_id[i]);
    CHECK(a[i] != other_seed[i]);
  }
}

TEST_CASE("white noise follows the sample interval: sigma / sqrt(dt), the first over 1 / rate",
          "[imu]") {
  // The first sample of 4000 models (seeds) and the second one 20 ms after it, at 200 Hz: the
  // white noise's standard deviation is sigma sqrt(200) then sigma sqrt(50).
  ImuOptions options = Quiet();
  options.gyroscope_noise_density = 1e-3;
  const int seeds = 4000;
  double first = 0, second = 0;
  for (int seed = 0; seed < seeds; ++seed) {
    ImuModel model(options, static_cast<std::uint64_t>(seed));
    first +=
        std::pow(model.Measure(Sample(1000, {0, 0, 0}, {0, 0, 0})).angular_velocity_rad_s.x(), 2);
    second += std::pow(
        model.Measure(Sample(1000 + 20000000, {0, 0, 0}, {0, 0, 0})).angular_velocity_rad_s.x(), 2);
  }
  // The sample standard deviation of 4000 normals: relative spread 1 / sqrt(2 * 4000) = 1.1 %.
  CHECK(std::sqrt(first / seeds) == Approx(1e-3 * std::sqrt(200.0)).epsilon(0.045));
  CHECK(std::sqrt(second / seeds) == Approx(1e-3 * std::sqrt(50.0)).epsilon(0.045));
}

TEST_CASE("ImuOptions::Check refuses bad values naming the key", "[imu]") {
  CHECK_FALSE(ImuOptions{}.Check());
  auto key_of = [](auto change) {
    ImuOptions options;
    change(options);
    const auto problem = options.Check();
    return problem ? problem->key : std::string("(accepted)");
  };
  CHECK(key_of([](ImuOptions& o) { o.rate_hz = 0; }) == "rate_hz");
  CHECK(key_of([](ImuOptions& o) { o.rate_hz = 1001; }) == "rate_hz");
  CHECK(key_of([](ImuOptions& o) { o.rate_hz = std::nan(""); }) == "rate_hz");
  CHECK(key_of([](ImuOptions& o) { o.phase_s = -0.001; }) == "phase_s");
  CHECK(key_of([](ImuOptions& o) { o.phase_s = 0.005; }) == "phase_s");  // = 1 / 200 Hz
  CHECK(key_of([](ImuOptions& o) { o.phase_s = 0.0049; }) == "(accepted)");
  CHECK(key_of([](ImuOptions& o) { o.mount.pitch_deg = 100; }) == "mount.pitch_deg");
  CHECK(key_of([](ImuOptions& o) { o.gyroscope_noise_density = -1e-4; }) ==
        "gyroscope_noise_density");
  CHECK(key_of([](ImuOptions& o) { o.gyroscope_random_walk = 1; }) == "gyroscope_random_walk");
  CHECK(key_of([](ImuOptions& o) { o.accelerometer_noise_density = 2; }) ==
        "accelerometer_noise_density");
  CHECK(key_of([](ImuOptions& o) { o.accelerometer_random_walk = -1; }) ==
        "accelerometer_random_walk");
  CHECK(key_of([](ImuOptions& o) { o.gyroscope_bias_rad_s = {0, 0}; }) == "gyroscope_bias_rad_s");
  CHECK(key_of([](ImuOptions& o) {
          o.accelerometer_bias_m_s2 = {0, 0, std::nan("")};
        }) == "accelerometer_bias_m_s2");
  CHECK(key_of([](ImuOptions& o) {
          o.accelerometer_bias_m_s2 = {6, 0, 0};
        }) == "accelerometer_bias_m_s2");
  CHECK(key_of([](ImuOptions& o) { o.gyroscope_scale = {1, 2, 1}; }) == "gyroscope_scale");
  CHECK(key_of([](ImuOptions& o) {
          o.accelerometer_scale = {1, 1, 1, 1};
        }) == "accelerometer_scale");
  CHECK(key_of([](ImuOptions& o) {
          o.accelerometer_scale = {0.5, 1, 1};
        }) == "accelerometer_scale");
  CHECK(key_of([](ImuOptions& o) {
          o.gyroscope_misalignment_rad = {0, 0.1, 0};
        }) == "gyroscope_misalignment_rad");
  CHECK(key_of([](ImuOptions& o) {
          o.accelerometer_misalignment_rad = {-0.2, 0, 0};
        }) == "accelerometer_misalignment_rad");
  CHECK(key_of([](ImuOptions& o) { o.gyroscope_range_rad_s = 0; }) == "gyroscope_range_rad_s");
  CHECK(key_of([](ImuOptions& o) { o.accelerometer_range_m_s2 = 1e4; }) ==
        "accelerometer_range_m_s2");
  // The message names the element and the value.
  ImuOptions options;
  options.gyroscope_scale = {1, 1, 3};
  REQUIRE(options.Check());
  CHECK(options.Check()->message == "element z must lie in (0.5, 2) (got 3)");
}

}  // namespace
}  // namespace corridorsim::sim
