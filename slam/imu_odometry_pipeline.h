#pragma once
// The `imu_odometry` pipeline: wheel odometry for the translation (P1 eq. 13, the distance
// (s_l + s_r) / 2 along the midpoint heading, its variance from P1 eq. 17) and the gyroscope's
// yaw rate for the heading, with the gyroscope's z bias in the state. An EKF over
// (x, y, yaw, b_gz); docs/imu_odometry.md gives the model, its equations and the measured figures.
//
// - Heading: yaw advances at (w_z - b_gz), w_z the IMU's angular velocity rotated into the robot
//   frame by the IMU's mount (Calibration::imus), each sample held until the next (zero-order
//   hold). Its noise is Kalibr's continuous-time model (Furgale et al., "Unified temporal and
//   spatial calibration for multi-sensor systems", IROS 2013; Kalibr's IMU noise model wiki):
//   white rate noise of density sigma_g (a sample's sigma is sigma_g sqrt(rate)), so the yaw
//   variance grows by sigma_g^2 dt; the bias walks with variance sigma_bg^2 dt.
// - The bias is observed by comparing the gyroscope with the wheels over each odometry interval:
//   z = (integral of w_z - (s_r - s_l) / B) / dt measures b_gz, with the wheel turn's variance of
//   P1 eq. 17 (k (|s_l| + |s_r|) / B^2, times `wheel_yaw_inflation` for the systematic errors
//   E_d, E_b eq. 17 does not model) plus the gyroscope's own (sigma_g^2 dt), while the gyroscope
//   says the robot drives straight or stands (`max_update_turn_rate_rad_s`). When the wheels do not
//   turn at all the first term vanishes: the same update is then a zero-velocity update (the gyro
//   reads its bias), the strongest one. A wheel that slips reports a turn the robot did not make:
//   the update's NIS exceeds `gate_chi2` and it is refused (counted in rejected_updates), so the
//   heading rides through slips on the gyroscope alone; with both wheels rolling the same way the
//   excess turn also names the wheel and the distance it over-reported, which the translation
//   leaves out (`compensate_slips`: Borenstein and Feng's gyrodometry, ICRA 1996).
// It reads no camera and draws no random numbers (deterministic).

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "common/error.h"
#include "common/options_table.h"
#include "common/wheel_odometry_model.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

/// Scenario key `pipelines.imu_odometry` (the table in slam/pipeline_options.cpp).
struct ImuOdometryOptions {
  // k of P1 eq. 17 (m^2 per m): each wheel's distance has variance k |s|.
  double k_m = kDefaultWheelNoiseK_m;
  // The IMU to read (its sensor name); empty: the calibration's first IMU.
  std::string imu;
  // Prior standard deviation of the gyroscope's z bias (rad/s): a MEMS gyroscope's zero-rate
  // offset after its factory calibration (the BMI055's data sheet: +-1 deg/s before it).
  double initial_bias_sigma_rad_s = 0.01;
  // Factor on P1 eq. 17's wheel-turn variance in the bias update (>= 1): the wheels' systematic
  // errors (Borenstein's E_d, E_b) bias the turn they report; a larger factor makes the bias
  // follow them more slowly.
  double wheel_yaw_inflation = 1.0;
  // The bias update runs only while the gyroscope (less the bias) reports at most this turn rate
  // (rad/s): driving straight or standing. In turns the wheels' turn errors grow with the turn
  // (E_b, the scrub of an in-place turn on a slippery floor: dead reckoning's heading error moved
  // 0.38 rad over the first 180 deg turn of imu_slippery.yaml, seed 1) and would pull the bias
  // for the whole turn; straight, the wheels' turn error is eq. 17's noise and E_d's curvature.
  double max_update_turn_rate_rad_s = 0.05;
  // NIS gate of the bias update (chi-square, 1 dof; 10.83 = 99.9 %): slips are refused.
  double gate_chi2 = 10.83;
  // Gyrodometry (Borenstein & Feng, ICRA 1996): a gated interval's excess turn names the wheel
  // that slipped and the distance it over-reported, which is taken back from the translation.
  bool compensate_slips = true;
  // An odometry interval whose last IMU sample is older than this turns by the wheels (P1 eq. 13)
  // instead of the gyroscope: an IMU that stopped (or has not started) never holds a stale rate.
  double max_imu_gap_s = 0.1;
  std::optional<OptionsProblem> Check() const;
};
/// The keys of `pipelines.imu_odometry`.
const OptionTable<ImuOdometryOptions>& ImuOdometryOptionsTable();

class ImuOdometryPipeline : public Pipeline {
 public:
  /// `calibration` must pass Check() and hold an IMU (the one `options.imu` names, if it names
  /// one): else std::invalid_argument (the pipeline fails at its creation, naming the IMU).
  ImuOdometryPipeline(const ImuOdometryOptions& options, const Calibration& calibration,
                      std::uint64_t seed = 0);
  void Initialize(TimeNs stamp_ns, const SE2& world_from_robot) override;
  void OnOdometry(const WheelOdometry& odometry) override;
  /// Samples of other IMUs are ignored; a non-finite sample or one not after the previous one is
  /// refused and counted (health().rejected_updates).
  void OnImu(const ImuSample& sample) override;
  PoseEstimate Estimate() const override;
  std::map<std::string, double> stage_seconds() const override;
  PipelineHealth health() const override { return health_; }
  /// Its own measurement type (slam::MeasurementType): kTurnMeasurement, the wheels' turn over an
  /// odometry interval against the gyroscope's, 1 dof: the bias update's NIS (accepted) and the
  /// slip gate's (a slip: gated out).
  std::vector<MeasurementType> measurement_types() const override {
    return {{kTurnMeasurement, 1}};
  }
  std::vector<Innovation> TakeInnovations() override { return std::move(innovations_); }
  static constexpr const char* kTurnMeasurement = "wheel_gyro_turn";

  /// The state (x m, y m, yaw rad, b_gz rad/s) and its covariance, for tests and diagnostics.
  const Eigen::Vector4d& state() const { return x_; }
  const Eigen::Matrix4d& covariance() const { return P_; }
  /// The id of the IMU it reads.
  const std::string& imu_id() const { return imu_.id; }
  /// IMU samples refused (non-finite, out of order), bias updates gated out: both also counted
  /// in health().rejected_updates.
  int rejected_imu_samples() const { return rejected_imu_samples_; }
  int gated_bias_updates() const { return gated_bias_updates_; }
  /// Slips whose distance was taken back (compensate_slips).
  int compensated_slips() const { return compensated_slips_; }

 private:
  // Advances the heading from state_ns_ to `stamp_ns` at the held rate (w_z - b_gz), with its
  // process noise; accumulates the raw gyro turn of the interval into interval_gyro_rad_.
  void PropagateHeading(TimeNs stamp_ns);
  // The wheels' turn over an odometry interval against the gyro's.
  struct TurnComparison {
    double excess_turn_rad = 0.0;  // wheel turn - gyro turn (bias removed)
    double var_wheel_turn = 0.0;   // P1 eq. 17's, inflated (rad^2)
    double var_gyro_turn = 0.0;    // sigma_g^2 dt (rad^2)
    bool slip = false;             // the excess fails the gate
    double nis = 0.0;              // excess^2 / its variance (0 when the variance is 0)
  };
  TurnComparison CompareTurns(double left_m, double right_m, double interval_s) const;
  void UpdateBias(const TurnComparison& comparison, double interval_s);
  // One innovation of kTurnMeasurement at the current stamp.
  void ReportTurn(double nis, bool accepted);

  ImuOdometryOptions options_;
  double wheelbase_m_;
  ImuCalibration imu_;
  Eigen::Matrix3d robot_from_imu_rotation_;
  Eigen::Vector4d x_ = Eigen::Vector4d::Zero();
  Eigen::Matrix4d P_ = Eigen::Matrix4d::Zero();
  TimeNs state_ns_ = 0;     // the time the state refers to
  TimeNs odometry_ns_ = 0;  // the last odometry message's stamp (the interval's start)
  bool have_sample_ = false;
  TimeNs sample_ns_ = 0;            // the last accepted sample's stamp
  double held_rate_rad_s_ = 0.0;    // its z rate in the robot frame (raw, bias included)
  double interval_gyro_rad_ = 0.0;  // raw gyro turn since odometry_ns_ (bias included)
  double interval_turn_rad_ = 0.0;  // the turn applied to the state since odometry_ns_
  double interval_gyro_s_ = 0.0;    // the time since odometry_ns_ the gyro turned the state
  bool interval_on_gyro_ = true;    // the whole interval since odometry_ns_ was covered by samples
  PipelineHealth health_;
  std::vector<Innovation> innovations_;  // since the last TakeInnovations()
  int rejected_imu_samples_ = 0;
  int gated_bias_updates_ = 0;
  int compensated_slips_ = 0;
  std::chrono::steady_clock::duration predict_time_{};
  std::chrono::steady_clock::duration update_time_{};
};

}  // namespace corridorsim::slam
