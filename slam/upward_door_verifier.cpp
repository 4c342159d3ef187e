#include "slam/upward_door_verifier.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>

#include <opencv2/imgproc.hpp>

#include "common/options_checker.h"
#include "slam/upward_door_verifier_detail.h"

namespace corridorsim::slam {
namespace {

using door_detail::InFront;
using door_detail::kMaxLeafDepths;
using door_detail::LeafDepths;

// The sensor model's factor for an error (P3 Fig. 8d: Gaussian; P2: triangular).
double Likelihood(DoorSensorModel model, double error, double scale) {
  const double e = error / scale;
  if (model == DoorSensorModel::kGaussian) return std::exp(-0.5 * e * e);
  return std::max(0.0, 1.0 - std::abs(e));
}

}  // namespace

struct UpwardDoorVerifier::Sighting {
  Eigen::Vector3d ray_a, ray_b;             // unit rays to the column tops, world frame
  double bearing_a = 0.0, bearing_b = 0.0;  // world bearings from the camera centre
  double elevation_a = 0.0, elevation_b = 0.0;
  double bar_coverage = 0.0;  // the candidate's
};

std::optional<OptionsProblem> DoorVerifierOptions::Check() const {
  if (auto p = CheckOptionBounds(DoorVerifierOptionsTable(), *this)) return p;
  if (!(2.0 * min_column_clearance_m < min_door_width_m)) {
    return OptionsProblem{"min_column_clearance_m", "must be below min_door_width_m / 2"};
  }
  if (!(max_top_height_m > min_top_height_m)) {
    return OptionsProblem{"max_top_height_m", "must be above min_top_height_m"};
  }
  if (canny_high < canny_low) return OptionsProblem{"canny_high", "must be at least canny_low"};
  if (max_door_top_m < min_door_top_m) {
    return OptionsProblem{"max_door_top_m", "must be at least min_door_top_m"};
  }
  if (max_door_width_m < min_door_width_m) {
    return OptionsProblem{"max_door_width_m", "must be at least min_door_width_m"};
  }
  if (max_leaf_depth_m < min_leaf_depth_m) {
    return OptionsProblem{"max_leaf_depth_m", "must be at least min_leaf_depth_m (got " +
                                                  FormatNumber(max_leaf_depth_m) + " < " +
                                                  FormatNumber(min_leaf_depth_m) + ")"};
  }
  if ((max_leaf_depth_m - min_leaf_depth_m) / leaf_depth_step_m > kMaxLeafDepths - 1) {
    return OptionsProblem{"leaf_depth_step_m",
                          "gives more than 100 leaf depths between min_leaf_depth_m and "
                          "max_leaf_depth_m (got " +
                              FormatNumber(leaf_depth_step_m) + ")"};
  }
  if (InFront(min_leaf_depth_m + double(LeafDepths(*this) - 1) * leaf_depth_step_m)) {
    return OptionsProblem{"leaf_depth_step_m",
                          "leaves no depth at or behind the columns' plane between "
                          "min_leaf_depth_m and max_leaf_depth_m (got " +
                              FormatNumber(leaf_depth_step_m) + ")"};
  }
  return std::nullopt;
}

std::optional<ColumnSighting> SightColumnTop(const Eigen::Vector2d& pixel, const CameraModel& model,
                                             const SE3& robot_from_camera) {
  const Eigen::Vector3d ray = robot_from_camera.rotation() * model.Unproject(pixel);
  const double horizontal = std::hypot(ray.x(), ray.y());
  if (!(ray.z() > 0.0) || !(horizontal > 1e-9)) return std::nullopt;
  return ColumnSighting{std::atan2(ray.y(), ray.x()), std::atan2(ray.z(), horizontal)};
}

UpwardDoorVerifier::UpwardDoorVerifier(const DoorVerifierOptions& options, const CameraModel& model,
                                       const SE3& robot_from_camera)
    : options_(options),
      model_(model),
      robot_from_camera_(robot_from_camera),
      random_(options.seed, 0, "slam.upward_doors") {
  CheckOrDie(!options.Check(), "slam::UpwardDoorVerifier", "the options fail their Check()");
}

bool UpwardDoorVerifier::Initialise(Track* track, const Sighting& s, const SE3& world_from_camera) {
  const Eigen::Vector3d c = world_from_camera.translation();
  // Tops between the prior's heights, and no farther than max_range_m.
  const double lo = std::max(options_.min_top_height_m, c.z() + 0.05);
  double hi = options_.max_top_height_m;
  for (const Eigen::Vector3d& ray : {s.ray_a, s.ray_b}) {
    const double horizontal = std::hypot(ray.x(), ray.y());
    if (horizontal > 1e-9) hi = std::min(hi, c.z() + options_.max_range_m * ray.z() / horizontal);
  }
  if (!(hi > lo)) return false;
  const int n = options_.particles;
  track->particles.resize(std::size_t(n));
  track->weights.assign(std::size_t(n), 1.0 / n);
  for (DoorParticle& p : track->particles) {
    const double h = random_.Uniform(lo, hi);
    const std::array<Eigen::Vector3d, 2> rays{s.ray_a, s.ray_b};
    for (int i = 0; i < 2; ++i) {
      // The ray turned by a bearing error about the vertical, cut at the height h.
      const double turn = random_.Normal(0.0, options_.bearing_error_rad);
      const double ct = std::cos(turn), st = std::sin(turn);
      const Eigen::Vector3d& r = rays[std::size_t(i)];
      const Eigen::Vector3d turned(ct * r.x() - st * r.y(), st * r.x() + ct * r.y(), r.z());
      const double t = (h - c.z()) / turned.z();
      p(2 * i) = c.x() + t * turned.x();
      p(2 * i + 1) = c.y() + t * turned.y();
    }
    p(4) = h;
  }
  return true;
}

void UpwardDoorVerifier::Weigh(Track* track, const Sighting& s, const SE3& world_from_camera) {
  const Eigen::Vector3d c = world_from_camera.translation();
  const std::size_t n = track->particles.size();
  double total = 0.0;
  std::vector<double> weights(n);
  for (std::size_t k = 0; k < n; ++k) {
    const DoorParticle& p = track->particles[k];
    double w = track->weights[k];
    const double bearings[2] = {s.bearing_a, s.bearing_b};
    const double elevations[2] = {s.elevation_a, s.elevation_b};
    for (int i = 0; i < 2; ++i) {
      const double dx = p(2 * i) - c.x(), dy = p(2 * i + 1) - c.y();
      const double bearing = std::atan2(dy, dx);
      const double elevation = std::atan2(p(4) - c.z(), std::hypot(dx, dy));
      w *= Likelihood(options_.sensor_model, NormalizeAngle(bearing - bearings[i]),
                      options_.bearing_error_rad);
      w *= Likelihood(options_.sensor_model, elevation - elevations[i],
                      options_.elevation_error_rad);
    }
    weights[k] = w;
    total += w;
  }
  if (!(total > 1e-300)) {
    // No sample explains the sighting (a triangular model's zero, or a jump). Columns already
    // known (kVerifying) keep their samples: the sighting is an outlier (P2's triangular model
    // gives several per door). Otherwise start again from it.
    if (track->state == DoorTrackState::kVerifying) return;
    track->bar_coverages.clear();
    Initialise(track, s, world_from_camera);
    return;
  }
  track->weights = std::move(weights);
  double sum_sq = 0.0;
  for (double& w : track->weights) {
    w /= total;
    sum_sq += w * w;
  }
  if (1.0 / sum_sq >= 0.5 * double(n)) return;
  // Systematic resampling, then roughening.
  std::vector<DoorParticle> resampled(n);
  const double step = 1.0 / double(n);
  double u = random_.Uniform(0.0, step), cumulative = track->weights[0];
  std::size_t j = 0;
  for (std::size_t k = 0; k < n; ++k) {
    while (u > cumulative && j + 1 < n) cumulative += track->weights[++j];
    resampled[k] = track->particles[j];
    for (int d = 0; d < 5; ++d) resampled[k](d) += random_.Normal(0.0, options_.roughening_m);
    u += step;
  }
  track->particles = std::move(resampled);
  track->weights.assign(n, step);
}

double UpwardDoorVerifier::TopHeight(const Track& track) {
  double height = 0.0;
  for (std::size_t k = 0; k < track.particles.size(); ++k) {
    height += track.weights[k] * track.particles[k](4);
  }
  return height;
}

bool UpwardDoorVerifier::DoorSized(const Track& track, const Eigen::Vector4d& columns,
                                   double height) const {
  const double width = (columns.head<2>() - columns.tail<2>()).norm();
  std::vector<double> coverage = track.bar_coverages;
  const auto middle = coverage.begin() + std::ptrdiff_t(coverage.size() / 2);
  if (!coverage.empty()) std::nth_element(coverage.begin(), middle, coverage.end());
  return height >= options_.min_door_top_m && height <= options_.max_door_top_m &&
         width >= options_.min_door_width_m && width <= options_.max_door_width_m &&
         (coverage.empty() || *middle >= options_.min_median_bar_coverage);
}

void UpwardDoorVerifier::Restart(Track* track) {
  track->state = DoorTrackState::kEstimating;
  track->plane_rays.clear();
  track->ruled_out_px.clear();
}

DoorTrackReport UpwardDoorVerifier::Report(const Track& track) const {
  DoorTrackReport r;
  r.track_id = track.id;
  r.state = track.state;
  r.hausdorff_px = track.hausdorff_px;
  r.leaf_depth_m = track.leaf_depth_m;
  Eigen::Vector4d mean = Eigen::Vector4d::Zero();
  for (std::size_t k = 0; k < track.particles.size(); ++k) {
    mean += track.weights[k] * track.particles[k].head<4>();
  }
  Eigen::Matrix4d cov = Eigen::Matrix4d::Zero();
  for (std::size_t k = 0; k < track.particles.size(); ++k) {
    const Eigen::Vector4d d = track.particles[k].head<4>() - mean;
    cov += track.weights[k] * d * d.transpose();
  }
  r.columns = mean;
  r.covariance = cov;
  return r;
}

void UpwardDoorVerifier::Spread(const Track& track, const Eigen::Vector3d& c,
                                DoorTrackReport* report) const {
  for (int col = 0; col < 2; ++col) {
    const Eigen::Vector2d mean_xy = report->columns.segment<2>(2 * col) - c.head<2>();
    const double mean_bearing = std::atan2(mean_xy.y(), mean_xy.x());
    double mean = 0.0, sq = 0.0, bearing_sq = 0.0, w = 0.0;
    for (std::size_t k = 0; k < track.particles.size(); ++k) {
      const Eigen::Vector2d xy = track.particles[k].segment<2>(2 * col) - c.head<2>();
      const double r = xy.norm();
      const double b = NormalizeAngle(std::atan2(xy.y(), xy.x()) - mean_bearing);
      mean += track.weights[k] * r;
      sq += track.weights[k] * r * r;
      bearing_sq += track.weights[k] * b * b;
      w += track.weights[k];
    }
    mean /= w;
    report->range_sigma_m(col) = std::sqrt(std::max(0.0, sq / w - mean * mean));
    report->bearing_sigma_rad(col) = std::sqrt(bearing_sq / w);
  }
}

std::vector<std::optional<DoorTrackReport>> UpwardDoorVerifier::Process(
    const std::vector<UpwardDoorCandidate>& candidates, const cv::Mat& grey, const SE2& pose) {
  ++frame_;
  if (path_.size() >= kPathPositions) path_.pop_front();
  path_.push_back(pose.translation());
  const SE3 world_from_camera = SE3::FromSE2(pose) * robot_from_camera_;
  const Eigen::Vector3d c = world_from_camera.translation();
  std::vector<std::optional<DoorTrackReport>> out(candidates.size());

  // Each candidate's sighting: rays to its column tops in the world.
  std::vector<std::optional<Sighting>> sightings(candidates.size());
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const std::optional<ColumnSighting> a =
        SightColumnTop(candidates[i].top_a_px, model_, robot_from_camera_);
    const std::optional<ColumnSighting> b =
        SightColumnTop(candidates[i].top_b_px, model_, robot_from_camera_);
    if (!a || !b) continue;
    Sighting s;
    s.ray_a = world_from_camera.rotation() * model_.Unproject(candidates[i].top_a_px);
    s.ray_b = world_from_camera.rotation() * model_.Unproject(candidates[i].top_b_px);
    s.bearing_a = NormalizeAngle(a->bearing_rad + pose.yaw());
    s.bearing_b = NormalizeAngle(b->bearing_rad + pose.yaw());
    s.elevation_a = a->elevation_rad;
    s.elevation_b = b->elevation_rad;
    s.bar_coverage = candidates[i].bar_coverage;
    sightings[i] = s;
  }

  const auto remember = [&](Track* track, const Sighting& s) {
    if (track->bar_coverages.size() >= kMaxSightings) {
      track->bar_coverages.erase(track->bar_coverages.begin());
    }
    track->bar_coverages.push_back(s.bar_coverage);
  };

  // Where a track's samples put each column, as seen from the camera now: the bearing of the
  // mean columns and the interval about it holding the samples' central 95 % (weighted). Before
  // the samples converge they spread along the rays of the first sighting, and only the samples
  // at the true range keep seeing the columns where they are as the camera moves: a candidate is
  // the track's when each column lies within associate_rad of that interval, not of the mean's
  // bearing (which drifts off the columns while the mean's range is wrong).
  struct Cloud {
    std::array<double, 2> mean{};         // world bearings of the mean columns
    std::array<double, 2> low{}, high{};  // the interval, relative to the mean
  };
  std::vector<std::pair<double, double>> offsets;  // (offset, weight), reused across tracks
  const auto cloud_of = [&](const Track& track) {
    Cloud cloud;
    const Eigen::Vector4d mean = Report(track).columns;
    offsets.resize(track.particles.size());
    for (int col = 0; col < 2; ++col) {
      cloud.mean[std::size_t(col)] = std::atan2(mean(2 * col + 1) - c.y(), mean(2 * col) - c.x());
      for (std::size_t k = 0; k < track.particles.size(); ++k) {
        const DoorParticle& p = track.particles[k];
        const double bearing = std::atan2(p(2 * col + 1) - c.y(), p(2 * col) - c.x());
        offsets[k] = {NormalizeAngle(bearing - cloud.mean[std::size_t(col)]), track.weights[k]};
      }
      std::sort(offsets.begin(), offsets.end());
      double cumulative = 0.0, low = offsets.front().first, high = offsets.back().first;
      bool have_low = false;
      for (const auto& [offset, weight] : offsets) {
        cumulative += weight;
        if (!have_low && cumulative >= 0.025) {
          low = offset;
          have_low = true;
        }
        if (cumulative >= 0.975) {
          high = offset;
          break;
        }
      }
      cloud.low[std::size_t(col)] = std::min(low, 0.0);
      cloud.high[std::size_t(col)] = std::max(high, 0.0);
    }
    return cloud;
  };
  // How far a bearing lies outside a column's interval (0 inside).
  const auto outside = [](const Cloud& cloud, int col, double bearing) {
    const double d = NormalizeAngle(bearing - cloud.mean[std::size_t(col)]);
    return std::max({0.0, cloud.low[std::size_t(col)] - d, d - cloud.high[std::size_t(col)]});
  };
  std::vector<Cloud> clouds;
  clouds.reserve(tracks_.size());
  for (const Track& track : tracks_) clouds.push_back(cloud_of(track));

  // Association: each candidate to the track whose columns it sees within associate_rad of the
  // samples' interval, nearest to the mean's bearings first; each track at most once.
  struct Pair {
    double error, mean_error;
    std::size_t candidate, track;
  };
  std::vector<Pair> pairs;
  for (std::size_t t = 0; t < tracks_.size(); ++t) {
    const Cloud& cloud = clouds[t];
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (!sightings[i]) continue;
      const double e = std::max(outside(cloud, 0, sightings[i]->bearing_a),
                                outside(cloud, 1, sightings[i]->bearing_b));
      const double mean_error =
          std::max(std::abs(NormalizeAngle(sightings[i]->bearing_a - cloud.mean[0])),
                   std::abs(NormalizeAngle(sightings[i]->bearing_b - cloud.mean[1])));
      if (e <= options_.associate_rad) pairs.push_back({e, mean_error, i, t});
    }
  }
  std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) {
    return std::tie(x.error, x.mean_error, x.candidate, x.track) <
           std::tie(y.error, y.mean_error, y.candidate, y.track);
  });
  std::vector<int> track_of(candidates.size(), -1);
  std::vector<bool> track_taken(tracks_.size(), false);
  for (const Pair& p : pairs) {
    if (track_of[p.candidate] >= 0 || track_taken[p.track]) continue;
    track_of[p.candidate] = int(p.track);
    track_taken[p.track] = true;
  }
  const std::size_t tracks_before = tracks_.size();

  cv::Mat edges;
  const auto edge_image = [&]() -> const cv::Mat& {
    if (edges.empty()) cv::Canny(grey, edges, options_.canny_low, options_.canny_high, 3, true);
    return edges;
  };

  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!sightings[i]) continue;
    const Sighting& s = *sightings[i];
    if (track_of[i] < 0) {
      // A candidate sharing a column with a track that a better candidate continues in this
      // frame is a duplicate (the same door paired with another line): not followed. A track
      // not continued now (its candidate lost) or found closed does not hold its columns: the
      // true pair of a door must not wait behind a wrong pairing of one of its columns.
      bool duplicate = false;
      for (std::size_t t = 0; t < tracks_before && !duplicate; ++t) {
        if (!track_taken[t] || tracks_[t].state == DoorTrackState::kClosed) continue;
        duplicate = std::min(outside(clouds[t], 0, s.bearing_a),
                             outside(clouds[t], 1, s.bearing_b)) <= options_.associate_rad;
      }
      if (duplicate || tracks_.size() >= std::size_t(options_.max_tracks)) continue;
      Track track;
      track.id = next_id_;
      if (!Initialise(&track, s, world_from_camera)) continue;
      ++next_id_;
      track.last_frame = frame_;
      track.hausdorff_px = std::numeric_limits<double>::quiet_NaN();
      track.leaf_depth_m = std::numeric_limits<double>::quiet_NaN();
      remember(&track, s);
      tracks_.push_back(std::move(track));
      track_taken.push_back(true);
      track_of[i] = int(tracks_.size() - 1);
      out[i] = Report(tracks_.back());
      continue;
    }
    Track& track = tracks_[std::size_t(track_of[i])];
    track.last_frame = frame_;
    if (track.state == DoorTrackState::kClosed) {
      out[i] = Report(track);
      continue;
    }
    Weigh(&track, s, world_from_camera);
    remember(&track, s);
    DoorTrackReport report = Report(track);
    if (track.state == DoorTrackState::kEstimating) {
      const double spread = std::sqrt(report.covariance.diagonal().maxCoeff());
      if (spread < options_.converged_sigma_m) {
        // The closed-door assumption (P3 Fig. 7): the opening's edge points on the plane.
        const double height = TopHeight(track);
        if (!DoorSized(track, report.columns, height)) {
          // Not a door's size (a cabinet, a poster, columns of two different things).
          track.state = DoorTrackState::kClosed;
          report.state = track.state;
          report.decided_now = true;
          out[i] = std::move(report);
          continue;
        }
        std::vector<Eigen::Vector2d> pixels;
        std::vector<Eigen::Vector3d> points;
        EdgesInOpening(edge_image(), world_from_camera, report.columns, height, &pixels, &points);
        if (int(points.size()) >= options_.min_edge_points) {
          const std::size_t stride = (points.size() + std::size_t(options_.max_edge_points) - 1) /
                                     std::size_t(options_.max_edge_points);
          for (std::size_t k = 0; k < points.size(); k += stride) {
            track.plane_rays.push_back((points[k] - c).normalized());
          }
          track.plane_view = world_from_camera;
          track.plane_columns = report.columns;
          track.plane_height = height;
          track.state = DoorTrackState::kVerifying;
        }
      }
    } else if (track.state == DoorTrackState::kVerifying &&
               Test(&track, edge_image(), world_from_camera)) {
      report = Report(track);
      report.decided_now = true;
      report.particles = track.particles;
    }
    report.state = track.state;
    report.hausdorff_px = track.hausdorff_px;
    Spread(track, c, &report);
    out[i] = std::move(report);
  }

  // Tracks whose columns are known but that no candidate continued in this frame: the test needs
  // only the opening's edges (a door passed abeam is often not paired in its last frames).
  opened_without_candidate_.clear();
  for (std::size_t t = 0; t < tracks_before; ++t) {
    Track& track = tracks_[t];
    if (track_taken[t] || track.state != DoorTrackState::kVerifying) continue;
    if (!Test(&track, edge_image(), world_from_camera)) continue;
    // Tested: still the track's sighting of the opening (not forgotten before its decision).
    track.last_frame = frame_;
    if (track.state != DoorTrackState::kOpen) continue;
    DoorTrackReport report = Report(track);
    report.decided_now = true;
    report.particles = track.particles;
    Spread(track, c, &report);
    opened_without_candidate_.push_back(std::move(report));
  }

  // Open tracks leave (the SLAM holds them now); tracks unseen for long are forgotten.
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const Track& t) {
                                 return t.state == DoorTrackState::kOpen ||
                                        frame_ - t.last_frame >= options_.forget_after_frames;
                               }),
                tracks_.end());
  return out;
}

}  // namespace corridorsim::slam
