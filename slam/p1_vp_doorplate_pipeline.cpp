#include "slam/p1_vp_doorplate_pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "common/options_checker.h"
#include "slam/ekf/measurement_models.h"
#include "slam/mapping/semantic_map.h"

namespace corridorsim::slam {
namespace {

constexpr double kDegToRad = M_PI / 180.0;

}  // namespace

std::optional<OptionsProblem> P1VpDoorplateOptions::Check() const {
  return CheckOptionBounds(P1VpDoorplateOptionsTable(), *this);
}

P1VpDoorplatePipeline::P1VpDoorplatePipeline(const P1VpDoorplateOptions& options,
                                             const Calibration& calibration,
                                             std::uint64_t /*seed: draws nothing*/)
    : EkfPipeline(calibration.wheelbase_m, options.k_m), options_(options) {
  CheckOrDie(!calibration.Check(), "slam::P1VpDoorplatePipeline",
             "the calibration fails its Check()");
  if (const CameraCalibration* front = calibration.Find("front")) front_ = *front;
  if (const CameraCalibration* lateral = calibration.Find("lateral")) lateral_ = *lateral;
  if (options_.use_door_plates) {
    models_ = DoorPlateModels::Load(options_.models_dir);
    CheckModelsFit(*models_, options_.door_plates, options_.models_dir);
  }
  if (options_.octomap && front_ && front_->depth) {
    mapper_ = std::make_unique<OccupancyMapper>(options_.octomap_map, *front_);
  }
}

P1VpDoorplatePipeline::~P1VpDoorplatePipeline() = default;

std::vector<std::string> P1VpDoorplatePipeline::cameras_used() const {
  std::vector<std::string> cameras;
  if (options_.use_vanishing_point || options_.octomap) cameras.push_back("front");
  if (options_.use_door_plates) cameras.push_back("lateral");
  return cameras;
}

void P1VpDoorplatePipeline::OnCamera(const CameraInput& input) {
  const std::string& id = input.image.camera_id;
  const CameraCalibration* calibration = id == "front"     ? (front_ ? &*front_ : nullptr)
                                         : id == "lateral" ? (lateral_ ? &*lateral_ : nullptr)
                                                           : nullptr;
  if (!state_ || calibration == nullptr) return;
  const auto last = last_frame_ns_.find(id);
  if (FrameProblem(input, *calibration, last == last_frame_ns_.end() ? -1 : last->second)) {
    ++health_.rejected_frames;
    return;
  }
  last_frame_ns_[id] = input.image.stamp_ns;
  const Clock::time_point t_frame = Clock::now();
  octomap_seconds_in_frame_ = 0.0;
  if (id == "front") OnFront(input);
  if (id == "lateral") OnLateral(input);
  // P1 Fig. 16: the filter's cost of the frame (the OctoMap's insertion is mapping, not the
  // filter) against the landmarks in its state (the vanishing point and the plates).
  frame_times_.push_back({input.image.stamp_ns, static_cast<int>(Landmarks().size()),
                          std::max(0.0, SecondsSince(t_frame) - octomap_seconds_in_frame_)});
}

void P1VpDoorplatePipeline::OnFront(const CameraInput& input) {
  const TimeNs stamp_ns = input.image.stamp_ns;
  if (options_.use_vanishing_point) {
    const Clock::time_point t0 = Clock::now();
    // A black frame carries no evidence: refused (and counted) before any detector runs.
    if (IsBlackImage(input.image.image)) {
      ++health_.rejected_frames;
    } else if (const std::optional<VanishingPoint> vp =
                   DetectVanishingPoint(input.image.image, options_.vanishing_point)) {
      clock_.Add("vp_detect", SecondsSince(t0));
      Detection d;
      d.stamp_ns = stamp_ns;
      d.camera_id = "front";
      d.type = LandmarkType::kVanishingPoint;
      d.pixel = vp->pixel_px;
      d.score = vp->quality.line_count;
      const Clock::time_point t1 = Clock::now();
      ObserveVanishingPoint(stamp_ns, vp->pixel_px.x(), &d);
      clock_.Add("update", SecondsSince(t1));
      detections_.push_back(std::move(d));
    } else {
      clock_.Add("vp_detect", SecondsSince(t0));
    }
  }
  if (mapper_ && input.depth) {
    if (HasNoValidDepth(input.depth->depth_m)) {
      ++health_.rejected_frames;
      return;
    }
    const Clock::time_point t0 = Clock::now();
    const Eigen::Vector3d x = state_->RobotPose();
    const SE3 world_from_camera =
        SE3::FromSE2(SE2(x.x(), x.y(), x.z())) * front_->robot_from_camera;
    mapper_->OnDepth(input.depth->depth_m, world_from_camera);
    octomap_seconds_in_frame_ = SecondsSince(t0);
    clock_.Add("octomap", octomap_seconds_in_frame_);
  }
}

void P1VpDoorplatePipeline::ObserveVanishingPoint(TimeNs stamp_ns, double u, Detection* detection) {
  const Eigen::Vector3d x = state_->RobotPose();
  const SE2 pose(x.x(), x.y(), x.z());
  const CameraModel& model = front_->model;
  const double sigma2 = options_.vp_sigma_px * options_.vp_sigma_px;
  // Association: a VP landmark stands for a corridor's direction, seen at either end: ahead
  // through its virtual-plane point p (P1 Fig. 10), or from the other way through the point
  // opposite it, 2 r - p (r the robot's position: the same direction turned by pi, as far away).
  // The hypothesis that projects into the image is the one in view (the other lies behind the
  // camera); the nearest by NIS if several.
  const VpLandmark* best = nullptr;
  ekf::Measurement best_measurement;
  double best_nis = 0.0;
  for (const VpLandmark& vp : vps_) {
    const Eigen::Vector2d p = state_->Value(vp.block);
    for (const bool reversed : {false, true}) {
      const Eigen::Vector2d seen = reversed ? Eigen::Vector2d(2.0 * pose.translation() - p) : p;
      Eigen::Matrix<double, 1, 3> d_pose;
      Eigen::Matrix<double, 1, 2> d_seen;
      const std::optional<double> predicted =
          ekf::VanishingPointU(pose, seen, front_->robot_from_camera, model, &d_pose, &d_seen);
      if (!predicted || *predicted < -0.5 * model.width() || *predicted > 1.5 * model.width()) {
        continue;
      }
      Eigen::Matrix<double, 1, 2> d_landmark = d_seen;
      if (reversed) {
        // seen = 2 r - p: d seen / d (x_r, y_r) = 2 I, d seen / d p = -I.
        d_pose.head<2>() += 2.0 * d_seen;
        d_landmark = -d_seen;
      }
      ekf::Measurement m;  // P1 eqs. 19, 21-24: z = u, H = [H_r 0 H_v 0]
      m.blocks = {ekf::EkfState::robot(), vp.block};
      m.residual = Eigen::VectorXd::Constant(1, u - *predicted);
      m.jacobian.resize(1, 5);
      m.jacobian << d_pose, d_landmark;
      m.noise = Eigen::MatrixXd::Constant(1, 1, sigma2);
      const std::optional<double> nis = state_->Nis(m);
      if (nis && (best == nullptr || *nis < best_nis)) {
        best = &vp;
        best_nis = *nis;
        best_measurement = std::move(m);
      }
    }
  }
  if (best != nullptr) {
    const ekf::UpdateResult result = state_->Update(best_measurement, options_.gate_chi2);
    Record(stamp_ns, LandmarkType::kVanishingPoint, result);
    if (result.accepted) detection->landmark_id = best->id;
    return;
  }
  // None in view: a new VP landmark on the virtual plane (P1 Fig. 10, eqs. 26-27), but only from
  // a point inside the image: a corridor's direction is seen ahead (P1: "observed in the corridor
  // frontage"). The detector also reports points up to max_outside_image_px beyond the image's
  // edge, which may update a landmark through the gate but never start one: seen while turning
  // they are the ones that go wrong (default.yaml, seed 1: a point at u = 917 px during the
  // last turn, 1160 px from the truth, had become a second, false VP landmark).
  if (u < -0.5 || u > model.width() - 0.5) return;
  Eigen::Matrix<double, 2, 3> d_landmark_d_pose;
  Eigen::Vector2d d_landmark_d_u;
  const std::optional<Eigen::Vector2d> landmark =
      ekf::InitVanishingPoint(pose, u, options_.vp_virtual_distance_m, front_->robot_from_camera,
                              model, &d_landmark_d_pose, &d_landmark_d_u);
  if (!landmark) return;
  ekf::Augmentation a;
  a.value = *landmark;
  a.blocks = {ekf::EkfState::robot()};
  a.d_value_d_blocks = d_landmark_d_pose;
  a.d_value_d_measurement = d_landmark_d_u;
  a.measurement_noise = Eigen::MatrixXd::Constant(1, 1, sigma2);
  VpLandmark vp;
  vp.id = next_landmark_id_++;
  vp.block = state_->Augment(a);
  vps_.push_back(vp);
  detection->landmark_id = vp.id;
  detection->new_landmark = true;
}

void P1VpDoorplatePipeline::OnLateral(const CameraInput& input) {
  if (!options_.use_door_plates || !models_) return;
  const TimeNs stamp_ns = input.image.stamp_ns;
  if (IsBlackImage(input.image.image)) {
    ++health_.rejected_frames;
    return;
  }
  const Clock::time_point t0 = Clock::now();
  const std::vector<DoorPlateDetection> plates =
      DetectDoorPlates(input.image.image, *models_, options_.door_plates);
  clock_.Add("plate_detect", SecondsSince(t0));
  const Clock::time_point t1 = Clock::now();
  ForgetStalePending(stamp_ns);
  for (const DoorPlateDetection& plate : plates) {
    Detection d;
    d.stamp_ns = stamp_ns;
    d.camera_id = "lateral";
    d.type = LandmarkType::kDoorPlate;
    d.box_px = Eigen::Vector4d(plate.box_px.min_x, plate.box_px.min_y, plate.box_px.max_x,
                               plate.box_px.max_y);
    d.plate_box = PlateBox::kNumberRegion;
    d.pixel = 0.5 * (d.box_px.head<2>() + d.box_px.tail<2>());
    d.score = plate.svm_score;
    if (!plate.reading.digits.empty()) d.recognition_score = plate.reading.min_score;
    // Only a reading whose every digit clears the threshold is a measurement (P1 section 3.2:
    // false readings are never registered).
    if (plate.reading.accepted) {
      d.label = plate.reading.number;
      ObservePlate(stamp_ns, plate.reading.number, d.pixel, &d);
    }
    detections_.push_back(std::move(d));
  }
  clock_.Add("update", SecondsSince(t1));
}

void P1VpDoorplatePipeline::ObservePlate(TimeNs stamp_ns, const std::string& number,
                                         const Eigen::Vector2d& pixel, Detection* detection) {
  const double u = pixel.x();
  const Eigen::Vector3d x = state_->RobotPose();
  const SE2 pose(x.x(), x.y(), x.z());
  const CameraModel& model = lateral_->model;
  const double sigma2 = options_.plate_sigma_px * options_.plate_sigma_px;

  // P1 Table 1: the signature alone associates a plate with its landmark.
  if (const auto it = plates_.find(number); it != plates_.end()) {
    Eigen::Matrix<double, 1, 3> d_pose;
    Eigen::Matrix<double, 1, 2> d_landmark;
    const std::optional<double> predicted =
        ekf::DoorPlateU(pose, state_->Value(it->second.block), options_.plate_height_m,
                        lateral_->robot_from_camera, model, &d_pose, &d_landmark);
    if (!predicted) {
      ++health_.rejected_updates;
      return;
    }
    // P1 eqs. 20-25. The signature row of eq. 20 has zero noise (eq. 25) and, the association
    // being by signature, zero residual: it adds nothing to the update and is left out.
    ekf::Measurement m;
    m.blocks = {ekf::EkfState::robot(), it->second.block};
    m.residual = Eigen::VectorXd::Constant(1, u - *predicted);
    m.jacobian.resize(1, 5);
    m.jacobian << d_pose, d_landmark;
    m.noise = Eigen::MatrixXd::Constant(1, 1, sigma2);
    const ekf::UpdateResult result = state_->Update(m, options_.gate_chi2);
    Record(stamp_ns, LandmarkType::kDoorPlate, result);
    if (result.accepted) {
      ++it->second.updates;
      detection->landmark_id = it->second.id;
    }
    return;
  }

  // A number not in the map: delayed initialisation (header comment).
  auto pending = pending_.find(number);
  if (pending == pending_.end()) {
    PendingPlate p;
    p.clone = state_->Clone(ekf::EkfState::robot());
    p.u_first = u;
    p.first_ns = stamp_ns;
    p.readings = 1;
    pending_.emplace(number, p);
    return;
  }
  PendingPlate& p = pending->second;
  ++p.readings;
  if (p.readings < options_.min_readings) return;
  const Eigen::Vector3d c = state_->Value(p.clone);
  Eigen::Matrix<double, 2, 3> d_first_pose;
  Eigen::Vector2d d_first_u;
  Eigen::Matrix<double, 2, 3> d_second_pose;
  Eigen::Vector2d d_second_u;
  const std::optional<ekf::PlateTriangulation> t = ekf::TriangulateDoorPlate(
      SE2(c.x(), c.y(), c.z()), p.u_first, pose, u, options_.plate_height_m,
      lateral_->robot_from_camera, model, &d_first_pose, &d_first_u, &d_second_pose, &d_second_u);
  if (!t || t->parallax_rad < options_.min_parallax_deg * kDegToRad) return;
  const SE3 world_from_camera = SE3::FromSE2(pose) * lateral_->robot_from_camera;
  const double range_m = (t->plate_in_world - world_from_camera.translation().head<2>()).norm();
  if (range_m > options_.max_plate_range_m) return;
  // A door plate sits at the nominal plate height: the triangulated plate's depth and the
  // reading's row v give the height it was seen at. Numbers on posters and notice boards, which
  // the reader may read as well as it reads plates, hang elsewhere and are refused here.
  const Eigen::Vector3d p_in_camera =
      world_from_camera.Inverse() *
      Eigen::Vector3d(t->plate_in_world.x(), t->plate_in_world.y(), options_.plate_height_m);
  const CameraIntrinsics intrinsics = model.intrinsics();
  const double seen_height_m = world_from_camera.translation().z() -
                               (pixel.y() - intrinsics.cy) * p_in_camera.z() / intrinsics.fy;
  if (!(std::abs(seen_height_m - options_.plate_height_m) <= options_.plate_height_tolerance_m)) {
    return;
  }
  // P1 eqs. 26-27 with A over the clone and the current pose and A_a over both u's.
  ekf::Augmentation a;
  a.value = t->plate_in_world;
  a.blocks = {p.clone, ekf::EkfState::robot()};
  a.d_value_d_blocks.resize(2, 6);
  a.d_value_d_blocks << d_first_pose, d_second_pose;
  a.d_value_d_measurement.resize(2, 2);
  a.d_value_d_measurement << d_first_u, d_second_u;
  a.measurement_noise = sigma2 * Eigen::MatrixXd::Identity(2, 2);
  PlateLandmark plate;
  plate.id = next_landmark_id_++;
  plate.block = state_->Augment(a);
  state_->Remove(p.clone);
  pending_.erase(pending);
  plates_.emplace(number, plate);
  detection->landmark_id = plate.id;
  detection->new_landmark = true;
}

void P1VpDoorplatePipeline::ForgetStalePending(TimeNs stamp_ns) {
  const TimeNs timeout_ns = FromSeconds(options_.pending_timeout_s);
  for (auto it = pending_.begin(); it != pending_.end();) {
    if (stamp_ns - it->second.first_ns > timeout_ns) {
      state_->Remove(it->second.clone);
      it = pending_.erase(it);
    } else {
      ++it;
    }
  }
}

void P1VpDoorplatePipeline::Record(TimeNs stamp_ns, LandmarkType type,
                                   const ekf::UpdateResult& result) {
  if (result.reason == ekf::UpdateReason::kNotPositiveDefinite) ++health_.non_positive_covariance;
  if (!result.accepted) ++health_.rejected_updates;
  if (std::isfinite(result.nis)) {
    innovations_.push_back({stamp_ns, type, result.nis, result.dof, result.accepted, {}});
  }
}

std::vector<LandmarkEstimate> P1VpDoorplatePipeline::Landmarks() const {
  std::vector<LandmarkEstimate> out;
  if (!state_) return out;
  const double vp_height_m = front_ ? front_->robot_from_camera.translation().z() : 0.0;
  for (const VpLandmark& vp : vps_) {
    LandmarkEstimate l;
    l.id = vp.id;
    l.type = LandmarkType::kVanishingPoint;
    l.position_in_world << state_->Value(vp.block), vp_height_m;
    l.covariance.setZero();
    l.covariance.topLeftCorner<2, 2>() = state_->Covariance(vp.block, vp.block);
    out.push_back(l);
  }
  for (const auto& [number, plate] : plates_) {
    LandmarkEstimate l;
    l.id = plate.id;
    l.type = LandmarkType::kDoorPlate;
    l.label = number;
    l.position_in_world << state_->Value(plate.block), options_.plate_height_m;
    l.covariance.setZero();  // the height is nominal, not estimated
    l.covariance.topLeftCorner<2, 2>() = state_->Covariance(plate.block, plate.block);
    // Converged once observed after its initialisation.
    l.status = plate.updates > 0 ? LandmarkStatus::kConverged : LandmarkStatus::kInitializing;
    out.push_back(l);
  }
  std::sort(out.begin(), out.end(),
            [](const LandmarkEstimate& a, const LandmarkEstimate& b) { return a.id < b.id; });
  return out;
}

std::vector<MapFile> P1VpDoorplatePipeline::TakeMaps() {
  std::vector<MapFile> maps;
  if (mapper_) maps.push_back({".bt", mapper_->BinaryBytes()});
  maps.push_back(FrameCostsCsv(frame_times_));  // P1 Fig. 16
  if (options_.use_door_plates) {
    maps.push_back({"_semantic.json", SemanticMapToJson(SemanticMapFromLandmarks(Landmarks()))});
  }
  return maps;
}

const octomap::OcTree* P1VpDoorplatePipeline::occupancy_map() const {
  return mapper_ ? &mapper_->octree() : nullptr;
}

}  // namespace corridorsim::slam
