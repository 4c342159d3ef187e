// lamp_ekf: a pipeline plugin for corridorsim, built against the installed SDK only
// (README.md is the tutorial). An EKF-SLAM over wheel odometry and the circular ceiling lamps an
// upward camera sees, built from the SDK's blocks:
//   - prediction: the differential-drive model of P1 (eqs. 13-17, common/wheel_odometry_model.h);
//   - detection: P3's circular-lamp detector (section II, eqs. 1-2, slam/features/ceiling_lamps.h);
//   - the filter: the EKF core (slam/ekf/ekf_state.h), with lamps as 2D points of the ceiling.
// Unlike P3's inverse-depth lamps (P3 eqs. 8-10), a lamp's height is known here (the ceiling
// height, an option): a detection's bearing meets the ceiling plane at one point, the lamp's
// position in the robot frame, z = R(yaw)^T (l - t) (the range-bearing model of P1 eq. 18 written
// in Cartesian form). Simpler than P3's, and enough to beat dead reckoning by far.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/camera_models.h"
#include "common/options_table.h"
#include "common/wheel_odometry_model.h"
#include "slam/ekf/ekf_state.h"
#include "slam/features/ceiling_lamps.h"
#include "slam/pipeline.h"
#include "slam/plugin.h"

namespace lamp_ekf {

using corridorsim::CameraModel;
using corridorsim::OptionsProblem;
using corridorsim::OptionTable;
using corridorsim::SE2;
using corridorsim::SE3;
using corridorsim::TimeNs;
using corridorsim::WheelOdometry;
namespace slam = corridorsim::slam;
namespace ekf = corridorsim::slam::ekf;

/// `pipelines.<name>` of type lamp_ekf.
struct LampEkfOptions {
  double k_m = corridorsim::kDefaultWheelNoiseK_m;  // k of P1 eq. 17 (m^2 per m of travel)
  double ceiling_height_m = 2.7;                    // the lamps' height above the floor
  double pixel_sigma_px = 2.0;                      // a lamp centre's standard deviation (px)
  double gate_chi2 =
      9.21;  // a detection updates the nearest lamp under this NIS (chi2 2 dof, 99 %)
  double new_lamp_chi2 = 40.0;    // farther than this from every lamp: a new lamp
  int max_lamps = 500;            // lamps in the state at most (bounds its size)
  double min_elevation_deg = 20;  // detections lower than this above the horizon are left out
  slam::CeilingLampOptions detector;
  std::optional<OptionsProblem> Check() const;
};

const OptionTable<LampEkfOptions>& LampEkfOptionsTable() {
  return corridorsim::StaticOptionTable<LampEkfOptions>([](OptionTable<LampEkfOptions>& t) {
    using O = LampEkfOptions;
    t.Add("k_m", &O::k_m, "m", "k of P1 eq. 17: each wheel distance has variance k |s|")
        .Range(0, 0.1);
    t.Add("ceiling_height_m", &O::ceiling_height_m, "m", "the lamps' height above the floor")
        .Range(0.5, 20);
    t.Add("pixel_sigma_px", &O::pixel_sigma_px, "px", "standard deviation of a lamp centre")
        .Range(0.05, 50);
    t.Add("gate_chi2", &O::gate_chi2, "",
          "a detection updates the nearest lamp when its NIS is below this")
        .Range(0.1, 1000);
    t.Add("new_lamp_chi2", &O::new_lamp_chi2, "",
          "a detection whose NIS to every lamp is above this starts a new lamp")
        .Range(0.1, 1e6);
    t.Add("max_lamps", &O::max_lamps, "", "lamps in the state at most").Range(1, 2000);
    t.Add("min_elevation_deg", &O::min_elevation_deg, "deg",
          "detections lower than this above the horizon are left out (their ceiling point is "
          "far and ill-conditioned)")
        .Range(1, 89);
    t.AddSection("detector", &O::detector, slam::CeilingLampOptionsTable(),
                 "the circular-lamp detector (P3 section II)", &slam::CeilingLampOptions::Check);
  });
}

std::optional<OptionsProblem> LampEkfOptions::Check() const {
  if (auto problem = corridorsim::CheckOptionBounds(LampEkfOptionsTable(), *this)) return problem;
  if (new_lamp_chi2 <= gate_chi2) {
    return OptionsProblem{"new_lamp_chi2", "must be greater than gate_chi2"};
  }
  return std::nullopt;
}

class LampEkfPipeline : public slam::Pipeline {
 public:
  LampEkfPipeline(const LampEkfOptions& options, const slam::Calibration& calibration,
                  std::uint64_t seed)
      : options_(options), wheelbase_m_(calibration.wheelbase_m) {
    options_.detector.seed = seed;  // the detector's random triples: of the run's seed
    if (const slam::CameraCalibration* camera = calibration.Find("upward")) camera_ = *camera;
    // Without an upward camera, cameras_used() still names it: the runner refuses the scenario
    // with a message at its `pipelines:` line.
  }

  std::vector<std::string> cameras_used() const override { return {"upward"}; }

  void Initialize(TimeNs stamp_ns, const SE2& world_from_robot) override {
    // The start pose is known exactly (the runner gives every pipeline the true one).
    state_.emplace(
        Eigen::Vector3d(world_from_robot.x(), world_from_robot.y(), world_from_robot.yaw()),
        Eigen::Matrix3d::Zero());
    stamp_ns_ = stamp_ns;
  }

  void OnOdometry(const WheelOdometry& odometry) override {
    if (!state_ || !std::isfinite(odometry.left_distance_m) ||
        !std::isfinite(odometry.right_distance_m) || odometry.stamp_ns < stamp_ns_) {
      ++health_.rejected_odometry;
      return;
    }
    const Eigen::Vector3d x = state_->RobotPose();
    Eigen::Matrix3d F;
    Eigen::Matrix<double, 3, 2> G;
    const SE2 next =
        corridorsim::ApplyWheelOdometry(SE2(x.x(), x.y(), x.z()), odometry.left_distance_m,
                                        odometry.right_distance_m, wheelbase_m_, &F, &G);
    const Eigen::Matrix2d Q = corridorsim::WheelOdometryNoise(
        odometry.left_distance_m, odometry.right_distance_m, options_.k_m);
    // P1 eqs. 14-16.
    state_->PredictRobot(Eigen::Vector3d(next.x(), next.y(), next.yaw()), F, G * Q * G.transpose());
    stamp_ns_ = odometry.stamp_ns;
  }

  void OnCamera(const slam::CameraInput& input) override {
    if (!state_ || !camera_ || input.image.camera_id != camera_->id) return;
    const CameraModel& model = camera_->model;
    const corridorsim::Image8& image = input.image.image;
    if (image.empty() || image.width != model.width() || image.height != model.height() ||
        input.image.stamp_ns < stamp_ns_) {
      ++health_.rejected_frames;
      return;
    }
    const slam::CeilingLampDetection found =
        slam::DetectCeilingLamps(image, &model, options_.detector);
    for (const slam::CeilingLampRegion& lamp : found.lamps) {
      const std::optional<Observation> z = Observe(lamp.center_px);
      if (!z) continue;
      slam::Detection detection;
      detection.stamp_ns = input.image.stamp_ns;
      detection.camera_id = camera_->id;
      detection.type = slam::LandmarkType::kLamp;
      detection.pixel = lamp.center_px;
      detection.radius_px = lamp.radius_px;
      Associate(*z, input.image.stamp_ns, &detection);
      detections_.push_back(detection);
    }
  }

  slam::PoseEstimate Estimate() const override {
    slam::PoseEstimate estimate;
    estimate.stamp_ns = stamp_ns_;
    if (!state_) return estimate;
    const Eigen::Vector3d x = state_->RobotPose();
    estimate.world_from_robot = SE2(x.x(), x.y(), x.z());
    estimate.covariance = state_->Covariance(ekf::EkfState::robot(), ekf::EkfState::robot());
    return estimate;
  }

  std::vector<slam::LandmarkEstimate> Landmarks() const override {
    std::vector<slam::LandmarkEstimate> out;
    if (!state_) return out;
    for (std::size_t i = 0; i < lamps_.size(); ++i) {
      slam::LandmarkEstimate landmark;
      landmark.id = static_cast<int>(i);
      landmark.type = slam::LandmarkType::kLamp;
      const Eigen::VectorXd l = state_->Value(lamps_[i]);
      landmark.position_in_world = Eigen::Vector3d(l.x(), l.y(), options_.ceiling_height_m);
      landmark.covariance.setZero();
      landmark.covariance.topLeftCorner<2, 2>() = state_->Covariance(lamps_[i], lamps_[i]);
      landmark.covariance(2, 2) = 1e-4;  // the height is an option, not estimated
      out.push_back(landmark);
    }
    return out;
  }

  std::vector<slam::Detection> TakeDetections() override { return std::move(detections_); }
  std::vector<slam::Innovation> TakeInnovations() override { return std::move(innovations_); }
  slam::PipelineHealth health() const override { return health_; }

 private:
  // A lamp centre as a point of the ceiling in the robot frame, and its covariance.
  struct Observation {
    Eigen::Vector2d z;
    Eigen::Matrix2d R;
  };

  std::optional<Observation> Observe(const Eigen::Vector2d& pixel) const {
    Eigen::Matrix<double, 3, 2> d_bearing_d_pixel;
    const Eigen::Vector3d bearing_c = camera_->model.Unproject(pixel, &d_bearing_d_pixel);
    const Eigen::Matrix3d robot_R_camera = camera_->robot_from_camera.rotation();
    const Eigen::Vector3d c = camera_->robot_from_camera.translation();
    const Eigen::Vector3d b = robot_R_camera * bearing_c;
    const double above = options_.ceiling_height_m - c.z();
    // Low above the horizon (or below it): the ceiling point is far and ill-conditioned.
    const double min_sin = std::sin(options_.min_elevation_deg * std::numbers::pi / 180.0);
    if (!(above > 0.0) || !(b.z() > min_sin * b.norm())) return std::nullopt;
    // p = c + s b on the plane z = ceiling height: s = (H - c_z) / b_z.
    const double s = above / b.z();
    Observation obs;
    obs.z = (c + s * b).head<2>();
    // d p / d b = s (I - b e_z^T / b_z), then through the rotation and the lens's Jacobian.
    Eigen::Matrix3d d_p_d_b = s * Eigen::Matrix3d::Identity();
    d_p_d_b.col(2) -= s * b / b.z();
    const Eigen::Matrix<double, 2, 2> J =
        (d_p_d_b * robot_R_camera * d_bearing_d_pixel).topRows<2>();
    const double var = options_.pixel_sigma_px * options_.pixel_sigma_px;
    obs.R = var * J * J.transpose();
    if (!obs.z.allFinite() || !obs.R.allFinite()) return std::nullopt;
    return obs;
  }

  // z = R(yaw)^T (l - t): the lamp seen from the robot; residual and Jacobian over (robot, lamp).
  ekf::Measurement Model(ekf::BlockId lamp, const Observation& obs) const {
    const Eigen::Vector3d x = state_->RobotPose();
    const Eigen::Vector2d l = state_->Value(lamp);
    const double c = std::cos(x.z()), s = std::sin(x.z());
    Eigen::Matrix2d Rt;
    Rt << c, s, -s, c;
    const Eigen::Vector2d d = l - x.head<2>();
    ekf::Measurement m;
    m.blocks = {ekf::EkfState::robot(), lamp};
    m.residual = obs.z - Rt * d;
    m.jacobian.resize(2, 5);
    m.jacobian.block<2, 2>(0, 0) = -Rt;
    m.jacobian.block<2, 1>(0, 2) = Eigen::Vector2d(-s * d.x() + c * d.y(), -c * d.x() - s * d.y());
    m.jacobian.block<2, 2>(0, 3) = Rt;
    m.noise = obs.R;
    return m;
  }

  void Associate(const Observation& obs, TimeNs stamp_ns, slam::Detection* detection) {
    double best_nis = std::numeric_limits<double>::infinity();
    std::size_t best = lamps_.size();
    for (std::size_t i = 0; i < lamps_.size(); ++i) {
      const std::optional<double> nis = state_->Nis(Model(lamps_[i], obs));
      if (nis && *nis < best_nis) {
        best_nis = *nis;
        best = i;
      }
    }
    if (best < lamps_.size() && best_nis < options_.gate_chi2) {
      const ekf::UpdateResult result = state_->Update(Model(lamps_[best], obs), options_.gate_chi2);
      innovations_.push_back(
          {stamp_ns, slam::LandmarkType::kLamp, result.nis, result.dof, result.accepted});
      if (!result.accepted) {
        ++health_.rejected_updates;
        if (result.reason == ekf::UpdateReason::kNotPositiveDefinite) {
          ++health_.non_positive_covariance;
        }
        return;
      }
      detection->landmark_id = static_cast<int>(best);
      return;
    }
    // Between the gates: too ambiguous to use either way.
    if (best_nis <= options_.new_lamp_chi2) return;
    if (static_cast<int>(lamps_.size()) >= options_.max_lamps) return;
    // P1 eqs. 26-27: l = t + R(yaw) z, from the robot block and the observation.
    const Eigen::Vector3d x = state_->RobotPose();
    const double c = std::cos(x.z()), s = std::sin(x.z());
    Eigen::Matrix2d R;
    R << c, -s, s, c;
    ekf::Augmentation a;
    a.value = x.head<2>() + R * obs.z;
    a.blocks = {ekf::EkfState::robot()};
    a.d_value_d_blocks.resize(2, 3);
    a.d_value_d_blocks.leftCols<2>().setIdentity();
    a.d_value_d_blocks.col(2) =
        Eigen::Vector2d(-s * obs.z.x() - c * obs.z.y(), c * obs.z.x() - s * obs.z.y());
    a.d_value_d_measurement = R;
    a.measurement_noise = obs.R;
    lamps_.push_back(state_->Augment(a));
    detection->landmark_id = static_cast<int>(lamps_.size() - 1);
    detection->new_landmark = true;
  }

  LampEkfOptions options_;
  double wheelbase_m_;
  std::optional<slam::CameraCalibration> camera_;
  std::optional<ekf::EkfState> state_;
  TimeNs stamp_ns_ = 0;
  std::vector<ekf::BlockId> lamps_;  // landmark id = index
  std::vector<slam::Detection> detections_;
  std::vector<slam::Innovation> innovations_;
  slam::PipelineHealth health_;
};

}  // namespace lamp_ekf

CORRIDORSIM_PLUGIN("lamp_ekf_example", "1.0.0", registrar) {
  registrar.Add<lamp_ekf::LampEkfOptions, lamp_ekf::LampEkfPipeline>(
      "lamp_ekf", &lamp_ekf::LampEkfOptionsTable);
}
