// Tests slam/imu_odometry_pipeline.cpp on synthetic sensor streams: the gyroscope's bias is
// estimated (at standstill and while driving straight), the heading follows the gyroscope through
// a wheel slip, the IMU's mount is applied, bad samples are refused, and the run is repeatable.
#include "slam/imu_odometry_pipeline.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>

#include "slam/odometry_pipeline.h"
#include "tests/support/odometry_message.h"
#include "tests/support/pioneer_calibration.h"

namespace corridorsim::slam {
namespace {

using test::OdometryMessage;

constexpr TimeNs kImuPeriodNs = 5'000'000;        // 200 Hz
constexpr TimeNs kOdometryPeriodNs = 20'000'000;  // 50 Hz
constexpr double kGyroBias = 0.01;                // rad/s, the z axis

ImuCalibration TestImu(const std::string& id = "imu", const SE3& mount = SE3()) {
  // A BMI055-like gyroscope (0.014 deg/s/sqrt(Hz)) and EuRoC's random walks.
  return ImuCalibration{id, mount, 200.0, 2.44e-4, 1.9393e-5, 1.47e-3, 3e-3};
}

Calibration WithImu(const ImuCalibration& imu) {
  Calibration c = test::PioneerCalibration();
  c.imus.push_back(imu);
  return c;
}

ImuSample Gyro(TimeNs stamp_ns, const Eigen::Vector3d& rate, const std::string& id = "imu") {
  ImuSample s;
  s.stamp_ns = stamp_ns;
  s.sensor_id = id;
  s.angular_velocity_rad_s = rate;
  s.linear_acceleration_m_s2 = Eigen::Vector3d(0, 0, 9.81);
  return s;
}

// Drives the robot at `speed` m/s and `turn_rate` rad/s for `seconds` from `*t_ns`, feeding the
// exact wheel distances at 50 Hz and the gyroscope (true rate + bias, in the IMU's axes) at
// 200 Hz in the bus's order (odometry before the IMU at one stamp). `extra_left_m` is added to
// the left wheel's distance of the first message (a slip).
void Drive(ImuOdometryPipeline& pipeline, TimeNs* t_ns, double seconds, double speed,
           double turn_rate, double bias = kGyroBias, double extra_left_m = 0.0,
           const Eigen::Matrix3d& robot_from_imu = Eigen::Matrix3d::Identity()) {
  const double b = test::PioneerCalibration().wheelbase_m;
  const TimeNs end_ns = *t_ns + static_cast<TimeNs>(std::llround(seconds * 1e9));
  const double dt = kOdometryPeriodNs * 1e-9;
  for (TimeNs t = *t_ns + kImuPeriodNs; t <= end_ns; t += kImuPeriodNs) {
    if (t % kOdometryPeriodNs == 0) {
      pipeline.OnOdometry(OdometryMessage(t, (speed - 0.5 * b * turn_rate) * dt + extra_left_m,
                                          (speed + 0.5 * b * turn_rate) * dt));
      extra_left_m = 0.0;
    }
    const Eigen::Vector3d rate_in_robot(0.0, 0.0, turn_rate + bias);
    pipeline.OnImu(Gyro(t, robot_from_imu.transpose() * rate_in_robot));
  }
  *t_ns = end_ns;
}

TEST_CASE("at standstill the gyroscope reads its bias: a zero-velocity update", "[slam][imu]") {
  ImuOdometryPipeline pipeline(ImuOdometryOptions{}, WithImu(TestImu()));
  pipeline.Initialize(0, SE2(1.0, 2.0, 0.3));
  TimeNs t = 0;
  Drive(pipeline, &t, 1.0, 0.0, 0.0);
  // The wheels stood still: their turn has no variance, each 20 ms update weighs only the
  // gyroscope's white noise (sigma_g^2 / dt), and the bias is known as the mean of 0.98 s of
  // gyroscope readings is (the first interval, before the first sample, is not compared).
  CHECK(pipeline.state()(3) == Approx(kGyroBias).margin(1e-5));
  CHECK(std::sqrt(pipeline.covariance()(3, 3)) == Approx(2.44e-4 / std::sqrt(0.98)).epsilon(0.01));
  // The heading drifted by the bias not yet known in the first updates only.
  CHECK(std::abs(pipeline.state()(2) - 0.3) < 2e-3);
  CHECK(pipeline.Estimate().world_from_robot.x() == 1.0);
  CHECK(pipeline.health().rejected_updates == 0);
}

TEST_CASE("driving straight on exact wheels, the bias converges to the gyroscope's",
          "[slam][imu]") {
  ImuOdometryOptions options;
  options.initial_bias_sigma_rad_s = 0.02;
  ImuOdometryPipeline pipeline(options, WithImu(TestImu()));
  pipeline.Initialize(0, SE2(0.0, 0.0, 0.0));
  TimeNs t = 0;
  Drive(pipeline, &t, 20.0, 0.3, 0.0);
  const double after_20s = std::abs(pipeline.state()(3) - kGyroBias);
  Drive(pipeline, &t, 40.0, 0.3, 0.0);
  const double after_60s = std::abs(pipeline.state()(3) - kGyroBias);
  // Each update weighs the wheels' turn noise of P1 eq. 17 (k = 1e-4): the estimate closes on
  // the bias as n P0 / (n P0 + R) does, 1.1e-3 and 3e-4 of 0.01 rad/s after 20 s and 60 s.
  CHECK(after_20s < 2e-3);
  CHECK(after_60s < 5e-4);
  CHECK(after_60s < after_20s);
  CHECK(pipeline.Estimate().world_from_robot.x() == Approx(18.0).epsilon(1e-3));
  // What the bias not yet known turned the heading by, before it converged.
  CHECK(std::abs(pipeline.Estimate().world_from_robot.yaw()) < 0.05);
}

TEST_CASE("a turn follows the gyroscope, not the wheels' turn error", "[slam][imu]") {
  // The wheels report 5 % less turn than the robot makes (an effective wheelbase 5 % longer than
  // nominal, Borenstein's E_b); the gyroscope (bias known) reports it exactly.
  ImuOdometryOptions options;
  options.initial_bias_sigma_rad_s = 0.0;
  ImuOdometryPipeline pipeline(options, WithImu(TestImu()));
  pipeline.Initialize(0, SE2(0.0, 0.0, 0.0));
  const double b = test::PioneerCalibration().wheelbase_m, rate = 0.5, dt = 0.02;
  const Eigen::Vector3d gyro(0, 0, rate);  // a known (zero) bias
  TimeNs t = 0;
  pipeline.OnImu(Gyro(0, gyro));
  for (int i = 1; i <= 100; ++i) {  // 2 s at 0.5 rad/s
    t += kOdometryPeriodNs;
    for (TimeNs s = t - kOdometryPeriodNs + kImuPeriodNs; s < t; s += kImuPeriodNs) {
      pipeline.OnImu(Gyro(s, gyro));
    }
    pipeline.OnOdometry(
        OdometryMessage(t, -0.5 * b * rate * dt / 1.05, 0.5 * b * rate * dt / 1.05));
    pipeline.OnImu(Gyro(t, gyro));
  }
  const PoseEstimate e = pipeline.Estimate();
  CHECK(e.stamp_ns == t);
  CHECK(e.world_from_robot.yaw() == Approx(1.0).margin(1e-9));
  CHECK(e.world_from_robot.translation().norm() < 1e-12);
}

TEST_CASE("a wheel slip leaves the heading on the gyroscope and its distance out", "[slam][imu]") {
  // Straight at 0.3 m/s; at 2 s the left wheel reports 3 cm it did not travel (slippery.yaml's
  // mean slip). Dead reckoning turns by 0.03 / B = 0.091 rad; imu_odometry does not.
  OdometryPipeline odometry(OdometryPipelineOptions{}, test::PioneerCalibration());
  odometry.Initialize(0, SE2());
  ImuOdometryOptions options;
  options.initial_bias_sigma_rad_s = 0.001;
  for (const bool compensate : {true, false}) {
    options.compensate_slips = compensate;
    ImuOdometryPipeline pipeline(options, WithImu(TestImu()));
    pipeline.Initialize(0, SE2());
    TimeNs t = 0;
    Drive(pipeline, &t, 2.0, 0.3, 0.0, 0.0);
    Drive(pipeline, &t, 2.0, 0.3, 0.0, 0.0, 0.03);
    const PoseEstimate e = pipeline.Estimate();
    CHECK(std::abs(e.world_from_robot.yaw()) < 1e-3);
    CHECK(pipeline.gated_bias_updates() == 1);
    CHECK(pipeline.health().rejected_updates == 1);
    // Its own measurement type: the turn comparisons as innovations, the slip gated out with a
    // NIS above the gate.
    REQUIRE(pipeline.measurement_types().size() == 1);
    CHECK(pipeline.measurement_types()[0].name == "wheel_gyro_turn");
    const std::vector<Innovation> innovations = pipeline.TakeInnovations();
    CHECK(innovations.size() > 100);
    std::size_t gated = 0;
    for (const Innovation& n : innovations) {
      CHECK(n.measurement == "wheel_gyro_turn");
      CHECK(n.dof == 1);
      CHECK(std::isfinite(n.nis));
      if (!n.accepted) {
        ++gated;
        CHECK(n.nis > options.gate_chi2);
      }
    }
    CHECK(gated == 1);
    CHECK(pipeline.TakeInnovations().empty());
    if (compensate) {
      // The excess turn named the left wheel and its 3 cm: the distance is the true 1.2 m.
      CHECK(pipeline.compensated_slips() == 1);
      CHECK(e.world_from_robot.x() == Approx(1.2).epsilon(1e-6));
    } else {
      CHECK(pipeline.compensated_slips() == 0);
      CHECK(e.world_from_robot.x() == Approx(1.215).epsilon(1e-6));  // half the slip
    }
  }
  // The same wheel stream through dead reckoning turns by the slip.
  TimeNs t = 0;
  const double dt = 0.02;
  for (int i = 1; i <= 200; ++i) {
    t += kOdometryPeriodNs;
    odometry.OnOdometry(OdometryMessage(t, 0.3 * dt + (i == 101 ? 0.03 : 0.0), 0.3 * dt));
  }
  CHECK(odometry.Estimate().world_from_robot.yaw() ==
        Approx(-0.03 / test::PioneerCalibration().wheelbase_m).epsilon(1e-9));
}

TEST_CASE("the IMU's mount rotates its axes into the robot's", "[slam][imu]") {
  // Upside down (roll 180 deg): the IMU's z axis points down and reads minus the robot's yaw rate.
  // Pitched up 90 deg: its x axis points up and carries the yaw rate.
  const Eigen::Matrix3d upside_down =
      Eigen::AngleAxisd(std::numbers::pi, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d pointing_up =
      Eigen::AngleAxisd(-std::numbers::pi / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (const Eigen::Matrix3d& mount : {upside_down, pointing_up}) {
    ImuOdometryPipeline pipeline(ImuOdometryOptions{},
                                 WithImu(TestImu("imu", SE3(mount, Eigen::Vector3d(0.1, 0, 0.3)))));
    pipeline.Initialize(0, SE2());
    TimeNs t = 0;
    Drive(pipeline, &t, 1.0, 0.0, 0.0, kGyroBias, 0.0, mount);  // the bias, from standing
    Drive(pipeline, &t, 2.0, 0.0, 0.4, kGyroBias, 0.0, mount);
    CHECK(pipeline.state()(3) == Approx(kGyroBias).margin(1e-4));
    CHECK(pipeline.Estimate().world_from_robot.yaw() == Approx(0.8).margin(3e-3));
  }
}

TEST_CASE("the IMU is the first one, or the one `imu` names; none is an error", "[slam][imu]") {
  Calibration calibration = WithImu(TestImu("first"));
  calibration.imus.push_back(TestImu("second"));
  CHECK(ImuOdometryPipeline(ImuOdometryOptions{}, calibration).imu_id() == "first");
  ImuOdometryOptions options;
  options.imu = "second";
  ImuOdometryPipeline second(options, calibration);
  CHECK(second.imu_id() == "second");
  // The other IMU's samples are not read (nor counted as refused).
  second.Initialize(0, SE2());
  second.OnImu(Gyro(kImuPeriodNs, Eigen::Vector3d(0, 0, 1.0), "first"));
  second.OnOdometry(OdometryMessage(kOdometryPeriodNs, 0.0, 0.0));
  CHECK(second.Estimate().world_from_robot.yaw() == 0.0);
  CHECK(second.rejected_imu_samples() == 0);
  options.imu = "third";
  CHECK_THROWS_AS(ImuOdometryPipeline(options, calibration), std::invalid_argument);
  CHECK_THROWS_AS(ImuOdometryPipeline(ImuOdometryOptions{}, test::PioneerCalibration()),
                  std::invalid_argument);
}

TEST_CASE("imu_odometry options are bounded and name the key", "[slam][imu]") {
  CHECK_FALSE(ImuOdometryOptions{}.Check());
  const auto problem_key = [](auto change) {
    ImuOdometryOptions o;
    change(o);
    const std::optional<OptionsProblem> p = o.Check();
    return p ? p->key : std::string("none");
  };
  CHECK(problem_key([](ImuOdometryOptions& o) { o.k_m = -1; }) == "k_m");
  CHECK(problem_key([](ImuOdometryOptions& o) { o.imu = "Bad-Name"; }) == "imu");
  CHECK(problem_key([](ImuOdometryOptions& o) { o.wheel_yaw_inflation = 0.5; }) ==
        "wheel_yaw_inflation");
  CHECK(problem_key([](ImuOdometryOptions& o) { o.gate_chi2 = 0; }) == "gate_chi2");
  CHECK(problem_key([](ImuOdometryOptions& o) { o.max_imu_gap_s = 0; }) == "max_imu_gap_s");
  CHECK(problem_key([](ImuOdometryOptions& o) {
          o.initial_bias_sigma_rad_s = std::numeric_limits<double>::quiet_NaN();
        }) == "initial_bias_sigma_rad_s");
}

TEST_CASE("non-finite and out-of-order IMU samples are refused and counted, not applied",
          "[slam][imu]") {
  ImuOdometryPipeline pipeline(ImuOdometryOptions{}, WithImu(TestImu()));
  pipeline.Initialize(0, SE2());
  TimeNs t = 0;
  Drive(pipeline, &t, 1.0, 0.0, 0.0);
  const Eigen::Vector4d before = pipeline.state();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  pipeline.OnImu(Gyro(t + kImuPeriodNs, Eigen::Vector3d(0, 0, nan)));
  ImuSample bad_accel = Gyro(t + kImuPeriodNs, Eigen::Vector3d(0, 0, 5.0));
  bad_accel.linear_acceleration_m_s2.x() = std::numeric_limits<double>::infinity();
  pipeline.OnImu(bad_accel);
  pipeline.OnImu(Gyro(t, Eigen::Vector3d(0, 0, 5.0)));                 // the last stamp again
  pipeline.OnImu(Gyro(t - kImuPeriodNs, Eigen::Vector3d(0, 0, 5.0)));  // older
  CHECK(pipeline.rejected_imu_samples() == 4);
  CHECK(pipeline.health().rejected_updates == 4);
  CHECK(pipeline.state() == before);
  CHECK(pipeline.covariance().allFinite());
  // The held rate is still the last good sample's (5 rad/s held for 5 ms would turn 0.025 rad):
  // standing on, the heading keeps still.
  Drive(pipeline, &t, 1.0, 0.0, 0.0);
  CHECK(std::abs(pipeline.state()(2) - before(2)) < 1e-4);
  CHECK(pipeline.rejected_imu_samples() == 4);
  // Bad odometry is refused as the odometry pipeline refuses it.
  pipeline.OnOdometry(OdometryMessage(t + kOdometryPeriodNs, nan, 0.0));
  pipeline.OnOdometry(OdometryMessage(t - kOdometryPeriodNs, 0.0, 0.0));
  CHECK(pipeline.health().rejected_odometry == 2);
}

TEST_CASE("without a recent IMU sample the heading turns by the wheels", "[slam][imu]") {
  ImuOdometryPipeline pipeline(ImuOdometryOptions{}, WithImu(TestImu()));
  pipeline.Initialize(0, SE2());
  const double b = test::PioneerCalibration().wheelbase_m;
  TimeNs t = 0;
  for (int i = 1; i <= 50; ++i) {  // 1 s turning at 0.5 rad/s; the IMU never reports
    t += kOdometryPeriodNs;
    pipeline.OnOdometry(OdometryMessage(t, -0.5 * b * 0.5 * 0.02, 0.5 * b * 0.5 * 0.02));
  }
  CHECK(pipeline.Estimate().world_from_robot.yaw() == Approx(0.5).epsilon(1e-12));
  CHECK(pipeline.Estimate().covariance(2, 2) > 0.0);
}

TEST_CASE("imu_odometry is deterministic: the same stream gives the same bytes", "[slam][imu]") {
  const auto run = [] {
    ImuOdometryPipeline pipeline(ImuOdometryOptions{}, WithImu(TestImu()));
    pipeline.Initialize(0, SE2(0.5, -0.5, 1.0));
    TimeNs t = 0;
    Drive(pipeline, &t, 3.0, 0.3, 0.2);
    Drive(pipeline, &t, 1.0, 0.3, 0.0, kGyroBias, 0.02);
    return std::make_pair(pipeline.state(), pipeline.covariance());
  };
  const auto a = run(), b = run();
  CHECK(std::memcmp(a.first.data(), b.first.data(), sizeof(double) * 4) == 0);
  CHECK(std::memcmp(a.second.data(), b.second.data(), sizeof(double) * 16) == 0);
}

}  // namespace
}  // namespace corridorsim::slam
