#include "slam/p3_upward_pipeline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>

#include <nlohmann/json.hpp>

#include "slam/ekf/upward_models.h"
#include "slam/features/image_conversion.h"

namespace corridorsim::slam {

std::optional<OptionsProblem> P3UpwardOptions::Check() const {
  if (auto p = CheckOptionBounds(P3UpwardOptionsTable(), *this)) return p;
  if (!(max_height_m > min_height_m)) {
    return OptionsProblem{"max_height_m", "must be above min_height_m"};
  }
  return std::nullopt;
}

P3UpwardOptions P3UpwardDefaults() { return P3UpwardOptions{}; }

P3UpwardOptions P3CornersDefaults() {
  P3UpwardOptions o;
  o.use_lamps = false;
  o.use_doors = false;
  return o;
}

P3UpwardOptions P2UpwardDefaults() {
  P3UpwardOptions o;
  o.use_lamps = false;
  o.corners.detector = CornerDetector::kHarris;
  o.door_verifier.sensor_model = DoorSensorModel::kTriangular;  // P2's sensor model
  return o;
}

struct P3UpwardPipeline::Observation {
  LandmarkType type = LandmarkType::kCorner;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  Eigen::Vector2d polar = Eigen::Vector2d::Zero();
  double sigma_px = 1.0;
  std::vector<float> patch;   // corners
  std::size_t detection = 0;  // index into detections_
  bool usable = true;         // far enough from the principal point
};

P3UpwardPipeline::P3UpwardPipeline(const P3UpwardOptions& options, const Calibration& calibration,
                                   std::uint64_t /*seed: the lamp detector's seed is an option*/)
    : EkfPipeline(calibration.wheelbase_m, options.k_m), options_(options) {
  CheckOrDie(!calibration.Check(), "slam::P3UpwardPipeline", "the calibration fails its Check()");
  CheckOrDie(!options.Check(), "slam::P3UpwardPipeline", "the options fail their Check()");
  if (const CameraCalibration* upward = calibration.Find("upward")) upward_ = *upward;
  if (upward_ && options.use_doors) {
    verifier_.emplace(options.door_verifier, upward_->model, upward_->robot_from_camera);
  }
  // P3 section V's prior as a Gaussian on the inverse height above the camera (docs/p3.md): its
  // mean the inverse of the middle height of the range, +2 sigma at the nearest height (min_height,
  // or min_above_camera above the camera); -2 sigma lies beyond the farthest, at or past infinity
  // (as Civera et al. take it: a far point's rho is known to be small, not its value).
  const double camera_z = upward_ ? ekf::CameraHeight(upward_->robot_from_camera) : 0.0;
  const double near = std::max(options.min_height_m - camera_z, options.min_above_camera_m);
  const double far = std::max(options.max_height_m - camera_z, 2.0 * near);
  rho_prior_ = 2.0 / (near + far);
  rho_prior_sigma_ = 0.5 * (1.0 / near - rho_prior_);
}

P3UpwardPipeline::~P3UpwardPipeline() = default;

void P3UpwardPipeline::OnCamera(const CameraInput& input) {
  if (!state_ || !upward_ || input.image.camera_id != "upward") return;
  if (FrameProblem(input, *upward_, last_frame_ns_) || IsBlackImage(input.image.image)) {
    ++health_.rejected_frames;
    return;
  }
  last_frame_ns_ = input.image.stamp_ns;
  ProcessFrame(input);
}

void P3UpwardPipeline::ProcessFrame(const CameraInput& input) {
  const TimeNs stamp_ns = input.image.stamp_ns;
  const SE3& mount = upward_->robot_from_camera;
  const CameraModel& model = upward_->model;
  const Eigen::Vector2d principal_point = model.principal_point();
  const Clock::time_point t_detect = Clock::now();
  const cv::Mat grey = GreyMat(input.image.image);
  const Eigen::Vector3d x = state_->RobotPose();
  const SE2 pose(x.x(), x.y(), x.z());
  // An upward camera's image turns by -yaw as the robot turns by yaw: patches sampled turned by
  // -yaw are aligned with the world.
  const double patch_angle = -pose.yaw();

  std::vector<Observation> observations;
  const auto observe = [&](LandmarkType type, const Eigen::Vector2d& pixel, double sigma_px) {
    Observation o;
    o.type = type;
    o.pixel = pixel;
    o.sigma_px = sigma_px;
    const double radius_px = (pixel - principal_point).norm();
    o.usable = radius_px >= options_.min_polar_radius_px && radius_px > 0.0;
    if (o.usable) o.polar = ekf::PixelToPolar(pixel, model);
    Detection d;
    d.stamp_ns = stamp_ns;
    d.camera_id = "upward";
    d.type = type;
    d.pixel = pixel;
    o.detection = detections_.size();
    detections_.push_back(d);
    return o;
  };
  if (options_.use_lamps) {
    for (const CeilingLampRegion& lamp :
         DetectCeilingLamps(input.image.image, &model, options_.lamps).lamps) {
      Observation o = observe(LandmarkType::kLamp, lamp.center_px, options_.lamp_sigma_px);
      detections_[o.detection].radius_px = std::max(lamp.radius_px, 1e-3);
      detections_[o.detection].score = lamp.sigma1_px;
      observations.push_back(std::move(o));
    }
  }
  if (options_.use_corners) {
    for (const CornerWithResponse& c : DetectCorners(grey, options_.corners)) {
      std::optional<std::vector<float>> patch =
          SamplePatch(grey, c.pixel_px, patch_angle, options_.corners.patch_half_px);
      if (!patch) continue;
      Observation o = observe(LandmarkType::kCorner, c.pixel_px, options_.corner_sigma_px);
      o.patch = std::move(*patch);
      detections_[o.detection].score = c.response;
      observations.push_back(std::move(o));
    }
  }
  // Door candidates (P3 section III-A) with their columns' bearings (P3 eq. 17's measurement).
  struct DoorObservation {
    UpwardDoorCandidate candidate;
    Eigen::Vector2d bearings = Eigen::Vector2d::Zero();
    std::size_t detection = 0;
  };
  std::vector<DoorObservation> door_observations;
  if (verifier_) {
    for (const UpwardDoorCandidate& c :
         DetectUpwardDoorCandidates(grey, principal_point, options_.doors).candidates) {
      const std::optional<ColumnSighting> a = SightColumnTop(c.top_a_px, model, mount);
      const std::optional<ColumnSighting> b = SightColumnTop(c.top_b_px, model, mount);
      if (!a || !b) continue;
      DoorObservation o;
      o.candidate = c;
      o.bearings = Eigen::Vector2d(a->bearing_rad, b->bearing_rad);
      Detection d;
      d.stamp_ns = stamp_ns;
      d.camera_id = "upward";
      d.type = LandmarkType::kDoor;
      d.pixel = 0.5 * (c.top_a_px + c.top_b_px);
      const Eigen::Vector2d lo = c.top_a_px.cwiseMin(c.top_b_px).array() - 1.0;
      const Eigen::Vector2d hi = c.top_a_px.cwiseMax(c.top_b_px).array() + 1.0;
      d.box_px << lo, hi;
      d.column_bearings_rad = o.bearings;
      d.score = c.bar_coverage;
      o.detection = detections_.size();
      detections_.push_back(d);
      door_observations.push_back(o);
    }
  }
  clock_.Add("detect", SecondsSince(t_detect));

  const Clock::time_point t_update = Clock::now();
  // Every landmark's prediction (P3 eq. 14).
  struct Prediction {
    Eigen::Vector2d pixel;
    Eigen::Vector2d polar;
    Eigen::Matrix<double, 2, 3> d_pose;
    Eigen::Matrix<double, 2, 5> d_landmark;
    bool in_image = false;  // projects into the image
    bool usable = false;    // and far enough from the principal point to be measured
  };
  std::vector<Prediction> predictions(landmarks_.size());
  for (std::size_t k = 0; k < landmarks_.size(); ++k) {
    Prediction& p = predictions[k];
    const ekf::InverseDepthPoint l = state_->Value(landmarks_[k].block);
    Eigen::Matrix<double, 2, 3> d_pixel_d_pose;
    Eigen::Matrix<double, 2, 5> d_pixel_d_landmark;
    const std::optional<Eigen::Vector2d> pixel =
        ekf::InverseDepthPixel(pose, l, mount, model, &d_pixel_d_pose, &d_pixel_d_landmark);
    if (!pixel || !model.IsInImage(*pixel)) continue;
    p.pixel = *pixel;
    p.in_image = true;
    if ((*pixel - principal_point).norm() < options_.min_polar_radius_px) {
      continue;
    }
    Eigen::Matrix2d d_polar_d_pixel;
    p.polar = ekf::PixelToPolar(*pixel, model, &d_polar_d_pixel);
    p.d_pose = d_polar_d_pixel * d_pixel_d_pose;
    p.d_landmark = d_polar_d_pixel * d_pixel_d_landmark;
    p.usable = true;
  }

  // Association (P3: each detection against the landmarks of its type predicted near it), each
  // landmark at most once per frame; lamps by the NIS alone, corners by their patch within the
  // gate.
  std::vector<ekf::Measurement> associated;
  std::vector<std::pair<std::size_t, std::size_t>> pairs;  // (observation, landmark)
  std::vector<double> associated_nis;
  std::vector<bool> taken(landmarks_.size(), false);
  std::vector<bool> explained(observations.size(), false);
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const Observation& o = observations[i];
    if (!o.usable) continue;
    std::optional<std::size_t> best;
    ekf::Measurement best_m;
    double best_nis = 0.0, best_correlation = -2.0;
    for (std::size_t k = 0; k < landmarks_.size(); ++k) {
      const Prediction& p = predictions[k];
      if (!p.usable || taken[k] || landmarks_[k].type != o.type ||
          (p.pixel - o.pixel).norm() > options_.search_radius_px) {
        continue;
      }
      double correlation = 0.0;
      if (o.type == LandmarkType::kCorner) {
        correlation = PatchCorrelation(o.patch, landmarks_[k].patch);
        if (correlation < options_.min_correlation) continue;
      }
      ekf::Measurement m;
      m.blocks = {ekf::EkfState::robot(), landmarks_[k].block};
      m.residual = o.polar - p.polar;
      m.residual(1) = std::remainder(m.residual(1), 2.0 * std::numbers::pi);
      m.jacobian.resize(2, 8);
      m.jacobian << p.d_pose, p.d_landmark;
      // Isotropic pixel noise in polar coordinates: sigma along r, sigma / r along theta.
      const double s2 = o.sigma_px * o.sigma_px;
      m.noise = Eigen::Vector2d(s2, s2 / (o.polar(0) * o.polar(0))).asDiagonal();
      const std::optional<double> nis = state_->Nis(m);
      if (!nis || *nis > options_.gate_chi2) continue;
      const bool better = o.type == LandmarkType::kCorner
                              ? (correlation > best_correlation ||
                                 (correlation == best_correlation && *nis < best_nis))
                              : (!best || *nis < best_nis);
      if (!best || better) {
        best = k;
        best_m = std::move(m);
        best_nis = *nis;
        best_correlation = correlation;
      }
    }
    if (best) {
      taken[*best] = true;
      explained[i] = true;
      detections_[o.detection].landmark_id = landmarks_[*best].id;
      associated.push_back(std::move(best_m));
      pairs.emplace_back(i, *best);
      associated_nis.push_back(best_nis);
    }
  }
  // Doors: each candidate against the registered doors by their two bearings (P3 eq. 17).
  const Eigen::Vector2d camera_xy = mount.translation().head<2>();
  struct DoorPair {
    std::size_t observation, door;
    double nis;
  };
  std::vector<DoorPair> door_pairs;
  std::vector<bool> door_explained(door_observations.size(), false);
  {
    // Every gated (candidate, door) pair, then the closest pairs first (AssignClosestFirst): a
    // candidate that shares one column with a door and takes the other from the room seen
    // through it gates too while the door is young, and must not take the door from the
    // candidate of its own two columns.
    std::vector<GatedPair> gated;
    std::vector<ekf::Measurement> measurements;
    for (std::size_t i = 0; i < door_observations.size(); ++i) {
      for (std::size_t k = 0; k < doors_.size(); ++k) {
        Eigen::Matrix<double, 2, 3> d_pose;
        Eigen::Matrix<double, 2, 4> d_door;
        const std::optional<Eigen::Vector2d> h =
            ekf::DoorBearings(pose, state_->Value(doors_[k].block), camera_xy, &d_pose, &d_door);
        if (!h) continue;
        ekf::Measurement m;
        m.blocks = {ekf::EkfState::robot(), doors_[k].block};
        m.residual = door_observations[i].bearings - *h;
        for (int c = 0; c < 2; ++c) {
          m.residual(c) = std::remainder(m.residual(c), 2.0 * std::numbers::pi);
        }
        m.jacobian.resize(2, 7);
        m.jacobian << d_pose, d_door;
        m.noise = Eigen::Matrix2d::Identity() * options_.door_sigma_rad * options_.door_sigma_rad;
        const std::optional<double> nis = state_->Nis(m);
        if (!nis || *nis > options_.gate_chi2) continue;
        gated.push_back({i, k, *nis});
        measurements.push_back(std::move(m));
      }
    }
    for (const std::size_t g : AssignClosestFirst(gated)) {
      const GatedPair& p = gated[g];
      door_explained[p.observation] = true;
      Detection& d = detections_[door_observations[p.observation].detection];
      d.landmark_id = doors_[p.landmark].id;
      d.open = true;
      associated.push_back(std::move(measurements[g]));
      door_pairs.push_back({p.observation, p.landmark, p.cost});
    }
  }
  if (!associated.empty()) {
    // Each was gated on its own; the stacked update (P3 eqs. 18-20) is not gated again.
    const ekf::UpdateResult result =
        state_->UpdateStacked(associated, std::numeric_limits<double>::infinity());
    if (result.reason == ekf::UpdateReason::kNotPositiveDefinite) {
      ++health_.non_positive_covariance;
    }
    if (!result.accepted) ++health_.rejected_updates;
    for (const DoorPair& p : door_pairs) {
      innovations_.push_back({stamp_ns, LandmarkType::kDoor, p.nis, 2, result.accepted, {}});
      if (result.accepted) {
        ++doors_[p.door].updates;
      } else {
        detections_[door_observations[p.observation].detection].landmark_id = -1;
      }
    }
    for (std::size_t a = 0; a < pairs.size(); ++a) {
      const Observation& o = observations[pairs[a].first];
      innovations_.push_back({stamp_ns, o.type, associated_nis[a], 2, result.accepted, {}});
      if (result.accepted) {
        ++landmarks_[pairs[a].second].updates;
      } else {
        detections_[o.detection].landmark_id = -1;
      }
    }
  }

  // P3 Fig. 16c: landmarks predicted in the image but rarely matched are deleted.
  for (std::size_t k = landmarks_.size(); k-- > 0;) {
    if (!predictions[k].usable) continue;
    PointLandmark& l = landmarks_[k];
    ++l.predicted;
    l.matched += taken[k];
    if (taken[k]) l.last_matched_ns = stamp_ns;
    if (l.predicted >= options_.delete_after &&
        l.matched < options_.min_match_fraction * l.predicted) {
      state_->Remove(l.block);
      landmarks_.erase(landmarks_.begin() + std::ptrdiff_t(k));
      predictions.erase(predictions.begin() + std::ptrdiff_t(k));
    }
  }

  // New landmarks from the unexplained detections clear of every predicted landmark, from the
  // updated pose, with the inverse-height prior (P3 section V).
  const Eigen::Vector3d x_new = state_->RobotPose();
  const SE2 updated(x_new.x(), x_new.y(), x_new.z());
  int new_corners = 0;
  const int matched_corners = int(std::count_if(pairs.begin(), pairs.end(), [&](const auto& p) {
    return observations[p.first].type == LandmarkType::kCorner;
  }));
  // A frame that finds the map empty (the first) may start more: its corners fix the heading of
  // all the map that follows them (docs/p3.md, "Where environment B's error comes from").
  const int regular_room =
      std::min(options_.max_new_corners_per_frame, options_.max_tracked_corners - matched_corners);
  const int corner_room =
      landmarks_.empty() ? std::max(options_.first_frame_corners, regular_room) : regular_room;
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const Observation& o = observations[i];
    if (explained[i] || !o.usable) continue;
    if (o.type == LandmarkType::kCorner && new_corners >= corner_room) continue;
    const bool clear =
        std::none_of(predictions.begin(), predictions.end(), [&](const Prediction& p) {
          return p.in_image && (p.pixel - o.pixel).norm() < options_.new_landmark_clearance_px;
        });
    if (!clear) continue;
    Eigen::Matrix<double, 5, 3> d_landmark_d_pose, d_landmark_d_z;
    const std::optional<ekf::InverseDepthPoint> l =
        ekf::InitInverseDepthPoint(updated, o.pixel, rho_prior_, mount, model, options_.min_ray_z,
                                   &d_landmark_d_pose, &d_landmark_d_z);
    if (!l) continue;
    if (landmarks_.size() >= std::size_t(options_.max_landmarks)) {
      // The state is full: the corner matched longest ago makes room, if out of view and stale.
      // Only landmarks older than this frame have a prediction (the ones this frame started
      // follow them in landmarks_, and were just seen).
      const TimeNs stale_before = stamp_ns - TimeNs(std::llround(options_.retire_after_s * 1e9));
      std::optional<std::size_t> oldest;
      for (std::size_t k = 0; k < predictions.size(); ++k) {
        const PointLandmark& candidate = landmarks_[k];
        if (candidate.type != LandmarkType::kCorner || predictions[k].in_image ||
            candidate.last_matched_ns > stale_before) {
          continue;
        }
        if (!oldest || candidate.last_matched_ns < landmarks_[*oldest].last_matched_ns) oldest = k;
      }
      if (!oldest) break;
      state_->Remove(landmarks_[*oldest].block);
      landmarks_.erase(landmarks_.begin() + std::ptrdiff_t(*oldest));
      predictions.erase(predictions.begin() + std::ptrdiff_t(*oldest));
    }
    ekf::Augmentation a;
    a.value = *l;
    a.blocks = {ekf::EkfState::robot()};
    a.d_value_d_blocks = d_landmark_d_pose;
    a.d_value_d_measurement = d_landmark_d_z;
    const double s2 = o.sigma_px * o.sigma_px;
    a.measurement_noise = Eigen::Vector3d(s2, s2, rho_prior_sigma_ * rho_prior_sigma_).asDiagonal();
    PointLandmark landmark;
    landmark.id = next_landmark_id_++;
    landmark.type = o.type;
    landmark.block = state_->Augment(a);
    landmark.patch = o.patch;
    landmark.last_matched_ns = stamp_ns;
    landmarks_.push_back(std::move(landmark));
    detections_[o.detection].landmark_id = landmarks_.back().id;
    detections_[o.detection].new_landmark = true;
    new_corners += o.type == LandmarkType::kCorner;
  }

  // Door candidates not explained by a registered door: the particle filter and the open-door
  // test (P3 section III-B); an open one becomes a landmark from its bearings and the filter's
  // ranges (P3 eq. 17 inverted, ekf::DoorFromBearings).
  if (verifier_) {
    std::vector<UpwardDoorCandidate> unexplained;
    std::vector<std::size_t> unexplained_index;
    // Predicted bearings of the registered doors (and of those registered below in this frame):
    // a candidate sharing a column with one (a frame edge, a room's wall seen through it) is
    // part of that door, not a new one.
    std::vector<Eigen::Vector2d> registered;
    for (const DoorLandmark& door : doors_) {
      if (auto h = ekf::DoorBearings(updated, state_->Value(door.block), camera_xy)) {
        registered.push_back(*h);
      }
    }
    const auto of_registered = [&](const Eigen::Vector2d& b) {
      const auto near = [&](double first, double second) {
        return std::abs(std::remainder(first - second, 2.0 * std::numbers::pi)) <=
               options_.door_verifier.associate_rad;
      };
      return std::any_of(registered.begin(), registered.end(), [&](const Eigen::Vector2d& h) {
        return near(b(0), h(0)) || near(b(0), h(1)) || near(b(1), h(0)) || near(b(1), h(1));
      });
    };
    for (std::size_t i = 0; i < door_observations.size(); ++i) {
      if (door_explained[i] || of_registered(door_observations[i].bearings)) continue;
      unexplained.push_back(door_observations[i].candidate);
      unexplained_index.push_back(i);
    }
    const std::vector<std::optional<DoorTrackReport>> reports =
        verifier_->Process(unexplained, grey, pose);
    // An open door becomes a landmark from the bearings (b_1, b_2) of its columns in the robot
    // frame, sigma (s_1, s_2), and the filter's ranges: the augmentation of P3 eq. 17 inverted.
    const auto add_door = [&](const DoorTrackReport& r, const Eigen::Vector2d& bearings,
                              const Eigen::Vector2d& bearing_sigma) {
      const Eigen::Vector2d c = ekf::CameraXY(updated, camera_xy);
      const Eigen::Vector4d z(bearings(0), bearings(1), (r.columns.head<2>() - c).norm(),
                              (r.columns.tail<2>() - c).norm());
      Eigen::Matrix<double, 4, 3> d_pose;
      Eigen::Matrix<double, 4, 4> d_z;
      ekf::Augmentation a;
      a.value = ekf::DoorFromBearings(updated, z, camera_xy, &d_pose, &d_z);
      a.blocks = {ekf::EkfState::robot()};
      a.d_value_d_blocks = d_pose;
      a.d_value_d_measurement = d_z;
      const double sa = std::max(2.0 * r.range_sigma_m(0), 0.05);
      const double sr = std::max(2.0 * r.range_sigma_m(1), 0.05);
      a.measurement_noise = Eigen::Vector4d(bearing_sigma(0) * bearing_sigma(0),
                                            bearing_sigma(1) * bearing_sigma(1), sa * sa, sr * sr)
                                .asDiagonal();
      DoorLandmark door;
      door.id = next_landmark_id_++;
      door.block = state_->Augment(a);
      double height = 0.0;
      for (const DoorParticle& p : r.particles) height += p(4);
      door.top_height_m = r.particles.empty() ? 0.0 : height / double(r.particles.size());
      door.registered_ns = stamp_ns;
      door.hausdorff_px = r.hausdorff_px;
      door.camera_xy = c;
      door.particles = r.particles;
      doors_.push_back(door);
      registered.push_back(bearings);  // DoorBearings of the new door's value
      return door.id;
    };
    const Eigen::Vector2d measured_sigma(options_.door_sigma_rad, options_.door_sigma_rad);
    for (std::size_t j = 0; j < reports.size(); ++j) {
      if (!reports[j]) continue;
      const DoorTrackReport& r = *reports[j];
      const DoorObservation& o = door_observations[unexplained_index[j]];
      Detection& d = detections_[o.detection];
      if (r.state == DoorTrackState::kClosed) d.open = false;
      if (r.state != DoorTrackState::kOpen || !r.decided_now) continue;
      d.open = true;
      d.landmark_id = add_door(r, o.bearings, measured_sigma);
      d.new_landmark = true;
    }
    // Doors decided open in a frame without a candidate of theirs: the bearings of the filter's
    // columns, with the samples' spread of them (at least a measurement's sigma). Not one
    // sharing a column with a registered door (two tracks of one door, one of them registered in
    // this frame or before: the candidates' rule above).
    for (const DoorTrackReport& r : verifier_->opened_without_candidate()) {
      const std::optional<Eigen::Vector2d> bearings =
          ekf::DoorBearings(updated, r.columns, camera_xy);
      if (bearings && !of_registered(*bearings)) {
        add_door(r, *bearings, r.bearing_sigma_rad.cwiseMax(measured_sigma));
      }
    }
  }
  clock_.Add("update", SecondsSince(t_update));
}

std::vector<MapFile> P3UpwardPipeline::TakeMaps() {
  std::vector<MapFile> maps;
  if (!verifier_ || !state_) return maps;
  nlohmann::ordered_json doors = nlohmann::ordered_json::array();
  for (const DoorLandmark& door : doors_) {
    const Eigen::Vector4d v = state_->Value(door.block);
    nlohmann::ordered_json particles = nlohmann::ordered_json::array();
    for (const DoorParticle& p : door.particles) {
      particles.push_back({p(0), p(1), p(2), p(3), p(4)});
    }
    nlohmann::ordered_json d;
    d["landmark_id"] = door.id;
    d["registered_s"] = double(door.registered_ns) * 1e-9;
    d["hausdorff_px"] = door.hausdorff_px;
    d["top_height_m"] = door.top_height_m;
    d["columns_m"] = {{v(0), v(1)}, {v(2), v(3)}};
    d["particles"] = particles;
    doors.push_back(d);
  }
  nlohmann::ordered_json map;
  map["format"] = "corridorsim.upward_doors";
  map["version"] = 1;
  map["frame"] = "world";
  map["particle"] = {"x_a_m", "y_a_m", "x_b_m", "y_b_m", "top_height_m"};
  map["doors"] = doors;
  maps.push_back({"_doors.json", map.dump(2) + "\n"});
  // P2 Fig. 12: the areas (docs/p3.md "Areas").
  nlohmann::ordered_json areas = nlohmann::ordered_json::array();
  for (const MapArea& area : Areas()) {
    nlohmann::ordered_json a;
    a["id"] = area.id;
    a["kind"] = area.kind == AreaKind::kCorridor ? "corridor" : "room";
    a["door_landmark_id"] =
        area.door_landmark_id >= 0 ? nlohmann::ordered_json(area.door_landmark_id) : nullptr;
    nlohmann::ordered_json polygon = nlohmann::ordered_json::array();
    for (const Eigen::Vector2d& p : area.polygon) polygon.push_back({p.x(), p.y()});
    a["polygon_m"] = area.polygon.empty() ? nlohmann::ordered_json(nullptr) : polygon;
    a["landmark_ids"] = area.landmark_ids;
    areas.push_back(a);
  }
  nlohmann::ordered_json division;
  division["format"] = "corridorsim.upward_areas";
  division["version"] = 1;
  division["frame"] = "world";
  division["room_depth_m"] = options_.areas.room_depth_m;
  division["room_reach_m"] = options_.areas.room_reach_m;
  division["min_depth_m"] = options_.areas.min_depth_m;
  division["areas"] = areas;
  maps.push_back({"_areas.json", division.dump(2) + "\n"});
  return maps;
}

std::vector<MapArea> P3UpwardPipeline::Areas() const {
  if (!verifier_ || !state_) return {};
  std::vector<AreaDoor> doors;
  for (const DoorLandmark& door : doors_) {
    const Eigen::Vector4d v = state_->Value(door.block);
    doors.push_back({door.id, v.head<2>(), v.tail<2>(), door.camera_xy});
  }
  std::vector<AreaPoint> points;
  for (const LandmarkEstimate& l : Landmarks()) {
    if (l.type != LandmarkType::kDoor) points.push_back({l.id, l.position_in_world.head<2>()});
  }
  return DivideAtDoors(doors, points, options_.areas);
}

std::vector<LandmarkEstimate> P3UpwardPipeline::Landmarks() const {
  std::vector<LandmarkEstimate> out;
  if (!state_ || !upward_) return out;
  const double camera_z = ekf::CameraHeight(upward_->robot_from_camera);
  for (const PointLandmark& l : landmarks_) {
    const ekf::InverseDepthPoint v = state_->Value(l.block);
    if (!(v(4) > 1e-3)) continue;  // at infinity: no point to report
    const Eigen::Matrix<double, 5, 5> cov = state_->Covariance(l.block, l.block);
    Eigen::Matrix<double, 3, 5> j;
    LandmarkEstimate e;
    e.id = l.id;
    e.type = l.type;
    e.position_in_world = ekf::InverseDepthToPoint(v, camera_z, &j);
    e.covariance = j * cov * j.transpose();
    // Converged once its height is known to a fifth (the inverse height's relative sigma).
    e.status = std::sqrt(cov(4, 4)) < 0.2 * v(4) ? LandmarkStatus::kConverged
                                                 : LandmarkStatus::kInitializing;
    out.push_back(e);
  }
  for (const DoorLandmark& door : doors_) {
    const Eigen::Vector4d v = state_->Value(door.block);
    const Eigen::Matrix4d cov = state_->Covariance(door.block, door.block);
    LandmarkEstimate e;
    e.id = door.id;
    e.type = LandmarkType::kDoor;
    e.position_in_world =
        Eigen::Vector3d(0.5 * (v(0) + v(2)), 0.5 * (v(1) + v(3)), door.top_height_m);
    Eigen::Matrix<double, 2, 4> mid;
    mid << 0.5, 0, 0.5, 0, 0, 0.5, 0, 0.5;
    e.covariance.setZero();
    e.covariance.topLeftCorner<2, 2>() = mid * cov * mid.transpose();
    e.covariance(2, 2) = 1.0;  // the height is the particle filter's, not the EKF's
    for (int c = 0; c < 2; ++c) {
      LandmarkPoint p;
      p.role = c == 0 ? "column_a" : "column_b";
      p.position_in_world = Eigen::Vector3d(v(2 * c), v(2 * c + 1), door.top_height_m);
      p.covariance.setZero();
      p.covariance.topLeftCorner<2, 2>() = cov.block<2, 2>(2 * c, 2 * c);
      p.covariance(2, 2) = 1.0;
      e.points.push_back(p);
    }
    e.status = LandmarkStatus::kConverged;
    out.push_back(e);
  }
  return out;
}

}  // namespace corridorsim::slam
