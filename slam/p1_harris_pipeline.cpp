#include "slam/p1_harris_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "slam/ekf/measurement_models.h"

namespace corridorsim::slam {
std::optional<OptionsProblem> P1HarrisOptions::Check() const {
  return CheckOptionBounds(P1HarrisOptionsTable(), *this);
}

P1HarrisPipeline::P1HarrisPipeline(const P1HarrisOptions& options, const Calibration& calibration,
                                   std::uint64_t /*seed: draws nothing*/)
    : EkfPipeline(calibration.wheelbase_m, options.k_m), options_(options) {
  CheckOrDie(!calibration.Check(), "slam::P1HarrisPipeline", "the calibration fails its Check()");
  if (const CameraCalibration* front = calibration.Find("front")) front_ = *front;
}

P1HarrisPipeline::~P1HarrisPipeline() = default;

Eigen::Matrix3d P1HarrisPipeline::MeasurementNoise(double depth_m) const {
  const double sigma_px2 = options_.pixel_sigma_px * options_.pixel_sigma_px;
  const double sigma_d = options_.depth_sigma_a_m + options_.depth_sigma_b * depth_m * depth_m;
  return Eigen::Vector3d(sigma_px2, sigma_px2, sigma_d * sigma_d).asDiagonal();
}

void P1HarrisPipeline::OnCamera(const CameraInput& input) {
  if (!state_ || !front_ || input.image.camera_id != "front") return;
  if (FrameProblem(input, *front_, last_frame_ns_) || !input.depth ||
      IsBlackImage(input.image.image) || HasNoValidDepth(input.depth->depth_m)) {
    ++health_.rejected_frames;
    return;
  }
  last_frame_ns_ = input.image.stamp_ns;
  const TimeNs stamp_ns = input.image.stamp_ns;
  const Clock::time_point t_frame = Clock::now();

  std::vector<HarrisCorner> corners =
      DetectHarrisCorners(input.image.image, &input.depth->depth_m, options_.corners);
  clock_.Add("detect", SecondsSince(t_frame));
  corners.erase(std::remove_if(corners.begin(), corners.end(),
                               [&](const HarrisCorner& c) {
                                 return !c.depth_m || *c.depth_m > options_.max_depth_m;
                               }),
                corners.end());
  if (corners.size() > static_cast<std::size_t>(options_.max_corners_per_frame)) {
    corners.resize(static_cast<std::size_t>(options_.max_corners_per_frame));  // strongest first
  }

  const Clock::time_point t_update = Clock::now();
  const SE3& robot_from_camera = front_->robot_from_camera;
  const CameraModel& model = front_->model;
  const Eigen::Vector3d x = state_->RobotPose();
  const SE2 pose(x.x(), x.y(), x.z());
  // Mahalanobis association of every corner against the predicted landmarks (each landmark at
  // most once per frame), then one stacked update of the associated ones (P1 eqs. 21-24), then
  // the unexplained corners become new landmarks from the updated pose (eqs. 26-27).
  std::vector<ekf::Measurement> associated;
  std::vector<std::size_t> associated_detection;
  std::vector<double> associated_nis;
  std::vector<std::size_t> unexplained;
  std::vector<bool> landmark_taken(landmarks_.size(), false);
  const std::size_t first_detection = detections_.size();
  for (const HarrisCorner& corner : corners) {
    const Eigen::Vector3d z(corner.pixel_px.x(), corner.pixel_px.y(), *corner.depth_m);
    const Eigen::Matrix3d R = MeasurementNoise(*corner.depth_m);
    Detection d;
    d.stamp_ns = stamp_ns;
    d.camera_id = "front";
    d.type = LandmarkType::kCorner;
    d.pixel = corner.pixel_px;
    d.score = corner.response;
    std::optional<std::size_t> best;
    ekf::Measurement best_m;
    double best_nis = 0.0;
    bool any_near = false;
    for (std::size_t k = 0; k < landmarks_.size(); ++k) {
      Eigen::Matrix3d d_pose;
      Eigen::Matrix3d d_point;
      const std::optional<Eigen::Vector3d> predicted = ekf::ProjectWorldPointWithDepth(
          pose, state_->Value(landmarks_[k].block), robot_from_camera, model, &d_pose, &d_point);
      if (!predicted || (predicted->head<2>() - z.head<2>()).norm() > options_.search_radius_px) {
        continue;
      }
      any_near = true;
      if (landmark_taken[k]) continue;
      ekf::Measurement m;
      m.blocks = {ekf::EkfState::robot(), landmarks_[k].block};
      m.residual = z - *predicted;
      m.jacobian.resize(3, 6);
      m.jacobian << d_pose, d_point;
      m.noise = R;
      const std::optional<double> nis = state_->Nis(m);
      if (nis && *nis <= options_.gate_chi2 && (!best || *nis < best_nis)) {
        best = k;
        best_nis = *nis;
        best_m = std::move(m);
      }
    }
    if (best) {
      landmark_taken[*best] = true;
      d.landmark_id = landmarks_[*best].id;
      associated.push_back(std::move(best_m));
      associated_detection.push_back(detections_.size());
      associated_nis.push_back(best_nis);
    } else if (!any_near) {
      unexplained.push_back(detections_.size());
    }
    detections_.push_back(std::move(d));
  }
  if (!associated.empty()) {
    // Each was gated on its own; the stacked update is not gated again.
    const ekf::UpdateResult result =
        state_->UpdateStacked(associated, std::numeric_limits<double>::infinity());
    if (result.reason == ekf::UpdateReason::kNotPositiveDefinite) {
      ++health_.non_positive_covariance;
    }
    for (std::size_t i = 0; i < associated.size(); ++i) {
      innovations_.push_back(
          {stamp_ns, LandmarkType::kCorner, associated_nis[i], 3, result.accepted, {}});
      if (!result.accepted) detections_[associated_detection[i]].landmark_id = -1;
    }
    if (!result.accepted) ++health_.rejected_updates;
  }
  const Eigen::Vector3d x_new = state_->RobotPose();
  const SE2 updated(x_new.x(), x_new.y(), x_new.z());
  for (const std::size_t index : unexplained) {
    if (landmarks_.size() >= static_cast<std::size_t>(options_.max_landmarks)) break;
    Detection& d = detections_[index];
    const double depth_m = corners[index - first_detection].depth_m.value();
    const Eigen::Vector3d z(d.pixel.x(), d.pixel.y(), depth_m);
    Eigen::Matrix3d d_point_d_pose;
    Eigen::Matrix3d d_point_d_z;
    const std::optional<Eigen::Vector3d> p = ekf::UnprojectRgbdPoint(
        updated, z, robot_from_camera, model, &d_point_d_pose, &d_point_d_z);
    if (!p) continue;
    ekf::Augmentation a;
    a.value = *p;
    a.blocks = {ekf::EkfState::robot()};
    a.d_value_d_blocks = d_point_d_pose;
    a.d_value_d_measurement = d_point_d_z;
    a.measurement_noise = MeasurementNoise(depth_m);
    PointLandmark l;
    l.id = next_landmark_id_++;
    l.block = state_->Augment(a);
    landmarks_.push_back(l);
    d.landmark_id = l.id;
    d.new_landmark = true;
  }
  clock_.Add("update", SecondsSince(t_update));
  frame_times_.push_back({stamp_ns, static_cast<int>(landmarks_.size()), SecondsSince(t_frame)});
}

std::vector<LandmarkEstimate> P1HarrisPipeline::Landmarks() const {
  std::vector<LandmarkEstimate> out;
  if (!state_) return out;
  for (const PointLandmark& l : landmarks_) {
    LandmarkEstimate e;
    e.id = l.id;
    e.type = LandmarkType::kCorner;
    e.position_in_world = state_->Value(l.block);
    e.covariance = state_->Covariance(l.block, l.block);
    out.push_back(e);
  }
  return out;
}

std::vector<MapFile> P1HarrisPipeline::TakeMaps() {
  return {FrameCostsCsv(frame_times_)};  // P1 Fig. 16
}

}  // namespace corridorsim::slam
