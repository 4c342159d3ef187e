#include "slam/imu_odometry_pipeline.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/wheel_odometry_model.h"

namespace corridorsim::slam {
namespace {

double Seconds(TimeNs ns) { return static_cast<double>(ns) * 1e-9; }

// A sensor name as docs/sensors.md allows it: 1 to 32 of a-z, 0-9, '_', starting with a letter.
bool IsSensorName(const std::string& name) {
  if (name.empty() || name.size() > 32 || name[0] < 'a' || name[0] > 'z') return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
  });
}

ImuCalibration ChooseImu(const std::string& name, const Calibration& calibration) {
  if (name.empty()) {
    if (calibration.imus.empty()) {
      throw std::invalid_argument(
          "imu_odometry reads an IMU, and the scenario enables none (add one under sensors:, "
          "docs/sensors.md)");
    }
    return calibration.imus.front();
  }
  for (const ImuCalibration& imu : calibration.imus) {
    if (imu.id == name) return imu;
  }
  throw std::invalid_argument("imu_odometry reads the IMU '" + name +
                              "', which is not enabled in sensors:");
}

}  // namespace

std::optional<OptionsProblem> ImuOdometryOptions::Check() const {
  if (auto problem = CheckOptionBounds(ImuOdometryOptionsTable(), *this)) return problem;
  if (!imu.empty() && !IsSensorName(imu)) {
    return OptionsProblem{"imu",
                          "must be empty or a sensor name: 1 to 32 of a-z, 0-9 and _, "
                          "starting with a letter"};
  }
  return std::nullopt;
}

ImuOdometryPipeline::ImuOdometryPipeline(const ImuOdometryOptions& options,
                                         const Calibration& calibration, std::uint64_t /*seed*/)
    : options_(options),
      wheelbase_m_(calibration.wheelbase_m),
      imu_(ChooseImu(options.imu, calibration)),
      robot_from_imu_rotation_(imu_.robot_from_imu.rotation()) {
  // The harness builds the calibration from checked options: an invalid one is a bug.
  CheckOrDie(!calibration.Check(), "slam::ImuOdometryPipeline",
             "the calibration fails its Check()");
}

void ImuOdometryPipeline::Initialize(TimeNs stamp_ns, const SE2& world_from_robot) {
  x_ << world_from_robot.x(), world_from_robot.y(), world_from_robot.yaw(), 0.0;
  P_.setZero();  // the start pose is known exactly; the bias is not
  P_(3, 3) = options_.initial_bias_sigma_rad_s * options_.initial_bias_sigma_rad_s;
  state_ns_ = odometry_ns_ = stamp_ns;
  interval_gyro_rad_ = interval_turn_rad_ = interval_gyro_s_ = 0.0;
  interval_on_gyro_ = true;
}

void ImuOdometryPipeline::PropagateHeading(TimeNs stamp_ns) {
  if (stamp_ns <= state_ns_) return;
  const double dt = Seconds(stamp_ns - state_ns_);
  Eigen::Matrix4d F = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d Q = Eigen::Matrix4d::Zero();
  // Kalibr's bias random walk: var b += sigma_bg^2 dt, whether or not a rate is held.
  Q(3, 3) = imu_.gyroscope_random_walk * imu_.gyroscope_random_walk * dt;
  if (have_sample_ && Seconds(stamp_ns - sample_ns_) <= options_.max_imu_gap_s) {
    // yaw += (w_z - b) dt at the held rate; Kalibr's white rate noise: var yaw += sigma_g^2 dt.
    const double turn = (held_rate_rad_s_ - x_(3)) * dt;
    x_(2) += turn;
    F(2, 3) = -dt;
    Q(2, 2) = imu_.gyroscope_noise_density * imu_.gyroscope_noise_density * dt;
    interval_gyro_rad_ += held_rate_rad_s_ * dt;
    interval_turn_rad_ += turn;
    interval_gyro_s_ += dt;
  } else {
    interval_on_gyro_ = false;  // no fresh rate: this interval turns by the wheels
  }
  P_ = F * P_ * F.transpose() + Q;
  state_ns_ = stamp_ns;
}

void ImuOdometryPipeline::OnImu(const ImuSample& sample) {
  if (sample.sensor_id != imu_.id) return;
  // Bad data never reaches the estimate: a non-finite sample, or one not after the previous
  // sample, is counted and dropped.
  if (!sample.angular_velocity_rad_s.allFinite() || !sample.linear_acceleration_m_s2.allFinite() ||
      (have_sample_ && sample.stamp_ns <= sample_ns_)) {
    ++rejected_imu_samples_;
    ++health_.rejected_updates;
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  PropagateHeading(sample.stamp_ns);  // up to this sample at the previous one's rate
  // The robot frame's z rate: the mount rotates the IMU's axes into the robot's
  // (docs/sensors.md: robot_from_imu).
  held_rate_rad_s_ = (robot_from_imu_rotation_ * sample.angular_velocity_rad_s).z();
  sample_ns_ = sample.stamp_ns;
  have_sample_ = true;
  predict_time_ += std::chrono::steady_clock::now() - t0;
}

void ImuOdometryPipeline::OnOdometry(const WheelOdometry& odometry) {
  if (!std::isfinite(odometry.left_distance_m) || !std::isfinite(odometry.right_distance_m) ||
      odometry.stamp_ns < odometry_ns_) {
    ++health_.rejected_odometry;
    return;
  }
  const auto t0 = std::chrono::steady_clock::now();
  PropagateHeading(odometry.stamp_ns);
  double left = odometry.left_distance_m, right = odometry.right_distance_m;
  const Eigen::Matrix2d wheel_noise = WheelOdometryNoise(left, right, options_.k_m);
  const double interval_s = Seconds(odometry.stamp_ns - odometry_ns_);
  // The wheels and the gyro compare only over an interval the gyro covered whole.
  const bool on_gyro = interval_on_gyro_;
  const bool compare =
      on_gyro && interval_s > 0.0 && std::abs(interval_gyro_s_ - interval_s) <= 1e-9;
  std::optional<TurnComparison> comparison;
  if (compare) comparison = CompareTurns(left, right, interval_s);
  if (comparison && comparison->slip && options_.compensate_slips && left * right > 0.0) {
    // Gyrodometry (Borenstein & Feng, ICRA 1996): where the wheels' turn disagrees with the
    // gyro's beyond the gate, a wheel slipped. A slip adds distance in the wheel's direction of
    // travel, so with both wheels rolling the same way the sign of the excess turn names the
    // wheel (the left one turns the robot right when it over-reports) and B |excess| is the
    // distance it reported beyond its travel: taken back (at most what it reported).
    const double extra = std::abs(comparison->excess_turn_rad) * wheelbase_m_;
    const bool left_slipped = comparison->excess_turn_rad * left < 0.0;
    double& wheel = left_slipped ? left : right;
    wheel -= std::copysign(std::min(extra, std::abs(wheel)), wheel);
    ++compensated_slips_;
  }
  // The pose at the interval's start: the heading less the turn applied since.
  const SE2 start(x_(0), x_(1), x_(2) - interval_turn_rad_);
  Eigen::Matrix3d F3;
  Eigen::Matrix<double, 3, 2> G3;
  if (on_gyro) {
    // P1 eq. 13 with the gyroscope's turn: wheels (d - B t / 2, d + B t / 2) turn the robot by
    // t and move it d = (s_l + s_r) / 2 along the midpoint heading. Only d carries wheel noise:
    // var d = (Q_ll + Q_rr) / 4 (P1 eq. 17), along that heading.
    const double d = 0.5 * (left + right), turn = interval_turn_rad_;
    const SE2 end = ApplyWheelOdometry(start, d - 0.5 * wheelbase_m_ * turn,
                                       d + 0.5 * wheelbase_m_ * turn, wheelbase_m_, &F3);
    Eigen::Matrix4d F = Eigen::Matrix4d::Identity();
    F.block<2, 1>(0, 2) = F3.block<2, 1>(0, 2);
    // The midpoint heading is yaw - turn / 2, and turn = integral (w_z - b): d mid / d b = t / 2.
    F.block<2, 1>(0, 3) = F3.block<2, 1>(0, 2) * (0.5 * interval_gyro_s_);
    const double mid = end.yaw() - 0.5 * turn;
    const Eigen::Vector4d g(std::cos(mid), std::sin(mid), 0.0, 0.0);
    const double var_d = 0.25 * (wheel_noise(0, 0) + wheel_noise(1, 1));
    x_(0) = end.x();
    x_(1) = end.y();
    x_(2) = NormalizeAngle(x_(2));
    P_ = F * P_ * F.transpose() + var_d * g * g.transpose();
  } else {
    // No fresh gyroscope rate over the interval: dead reckoning as the odometry pipeline does
    // (P1 eqs. 13-17); the bias only walks.
    const SE2 end = ApplyWheelOdometry(start, left, right, wheelbase_m_, &F3, &G3);
    x_ << end.x(), end.y(), end.yaw(), x_(3);
    P_.topLeftCorner<3, 3>() =
        F3 * P_.topLeftCorner<3, 3>() * F3.transpose() + G3 * wheel_noise * G3.transpose();
    P_.topRightCorner<3, 1>() = F3 * P_.topRightCorner<3, 1>();
    P_.bottomLeftCorner<1, 3>() = P_.topRightCorner<3, 1>().transpose();
  }
  P_ = 0.5 * (P_ + P_.transpose());
  predict_time_ += std::chrono::steady_clock::now() - t0;
  if (comparison) UpdateBias(*comparison, interval_s);
  odometry_ns_ = odometry.stamp_ns;
  interval_gyro_rad_ = interval_turn_rad_ = interval_gyro_s_ = 0.0;
  interval_on_gyro_ = true;
}

ImuOdometryPipeline::TurnComparison ImuOdometryPipeline::CompareTurns(double left, double right,
                                                                      double interval_s) const {
  TurnComparison c;
  // The wheels' turn over the interval (P1 eq. 13) less the gyro's (bias removed): what the bias
  // update explains, or a slip.
  c.excess_turn_rad = (right - left) / wheelbase_m_ - interval_turn_rad_;
  // Its variance: the wheels' (P1 eq. 17, inflated for the systematic errors eq. 17 leaves out;
  // 0 when the wheels stood still), the gyro's white noise (sigma_g^2 dt) and the bias's.
  c.var_wheel_turn = options_.wheel_yaw_inflation * options_.k_m *
                     (std::abs(left) + std::abs(right)) / (wheelbase_m_ * wheelbase_m_);
  c.var_gyro_turn = imu_.gyroscope_noise_density * imu_.gyroscope_noise_density * interval_s;
  const double var = c.var_wheel_turn + c.var_gyro_turn + P_(3, 3) * interval_s * interval_s;
  c.nis = var > 0.0 ? c.excess_turn_rad * c.excess_turn_rad / var : 0.0;
  c.slip = var > 0.0 ? c.nis > options_.gate_chi2 : c.excess_turn_rad != 0.0;
  return c;
}

void ImuOdometryPipeline::UpdateBias(const TurnComparison& c, double interval_s) {
  if (c.slip) {
    // A slipping wheel reports a turn the robot did not make: refused, the gyro carries on.
    ++gated_bias_updates_;
    ++health_.rejected_updates;
    if (c.nis > 0.0) ReportTurn(c.nis, false);
    return;
  }
  // Only while the gyroscope says the robot drives straight or stands (in turns the wheels' turn
  // errors grow with the turn); the wheels cannot say it: eq. 17's noise on one interval's turn
  // rate is larger than a turn's (0.18 rad/s at 0.34 m/s and 50 Hz on the default robot).
  if (std::abs(interval_turn_rad_) > options_.max_update_turn_rate_rad_s * interval_s) return;
  const auto t0 = std::chrono::steady_clock::now();
  // z = (raw gyro turn - wheel turn) / dt measures b_gz; its residual against the state is
  // -excess / dt, with R = (var wheel turn + var gyro turn) / dt^2.
  const double residual = -c.excess_turn_rad / interval_s;
  const double R = (c.var_wheel_turn + c.var_gyro_turn) / (interval_s * interval_s);
  const double S = P_(3, 3) + R;
  if (!(S > 0.0) || !std::isfinite(residual)) {
    // Both sides exact (noise-free IMU, still wheels, known bias) leave nothing to learn; a
    // negative or non-finite one is numerical trouble.
    if (!(S >= 0.0) || !std::isfinite(residual)) ++health_.non_positive_covariance;
    update_time_ += std::chrono::steady_clock::now() - t0;
    return;
  }
  ReportTurn(residual * residual / S, true);
  const Eigen::Vector4d K = P_.col(3) / S;
  x_ += K * residual;
  x_(2) = NormalizeAngle(x_(2));
  // Joseph form: P = (I - K H) P (I - K H)^T + K R K^T with H = e_4^T.
  Eigen::Matrix4d I_KH = Eigen::Matrix4d::Identity();
  I_KH.col(3) -= K;
  P_ = I_KH * P_ * I_KH.transpose() + R * K * K.transpose();
  P_ = 0.5 * (P_ + P_.transpose());
  update_time_ += std::chrono::steady_clock::now() - t0;
}

void ImuOdometryPipeline::ReportTurn(double nis, bool accepted) {
  Innovation n;
  n.stamp_ns = state_ns_;
  n.measurement = kTurnMeasurement;
  n.nis = nis;
  n.dof = 1;
  n.accepted = accepted;
  innovations_.push_back(n);
}

PoseEstimate ImuOdometryPipeline::Estimate() const {
  PoseEstimate e;
  e.stamp_ns = state_ns_;
  e.world_from_robot = SE2(x_(0), x_(1), x_(2));
  e.covariance = P_.topLeftCorner<3, 3>();
  return e;
}

std::map<std::string, double> ImuOdometryPipeline::stage_seconds() const {
  return {{"predict", std::chrono::duration<double>(predict_time_).count()},
          {"update", std::chrono::duration<double>(update_time_).count()}};
}

}  // namespace corridorsim::slam
