#include "slam/upward_door_verifier.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <tuple>

#include <opencv2/imgproc.hpp>

#include "common/options_checker.h"

namespace corridorsim::slam {
namespace {

constexpr int kMaxLeafDepths = 100;  // leaf depths tried at most (DoorVerifierOptions::Check)
// A verifying track's columns may move this many converged_sigma_m off the plane's.
constexpr double kMaxColumnShift = 4.0;

// The leaf depths tried: min_leaf_depth_m, then every leaf_depth_step_m up to max_leaf_depth_m.
std::size_t LeafDepths(const DoorVerifierOptions& o) {
  const double steps = (o.max_leaf_depth_m - o.min_leaf_depth_m) / o.leaf_depth_step_m;
  return std::size_t(std::clamp(int(std::floor(steps + 1e-9)) + 1, 1, kMaxLeafDepths));
}

// Whether a leaf depth lies in front of the columns' plane (min + k step: rounding aside).
bool InFront(double depth) { return depth < -1e-9; }

// The sensor model's factor for an error (P3 Fig. 8d: Gaussian; P2: triangular).
double Likelihood(DoorSensorModel model, double error, double scale) {
  const double e = error / scale;
  if (model == DoorSensorModel::kGaussian) return std::exp(-0.5 * e * e);
  return std::max(0.0, 1.0 - std::abs(e));
}

// Mean over `from` of the distance to the nearest point of `to` (P3 eq. 9's h_mod), by the
// distance transform of `to` drawn in the box `roi` of the image that holds both sets (the
// nearest point of `to` lies in it, so the distances are those of the whole image).
double ModifiedHausdorff(const std::vector<Eigen::Vector2d>& from,
                         const std::vector<Eigen::Vector2d>& to, const cv::Rect& roi) {
  if (from.empty()) return 0.0;
  cv::Mat image(roi.size(), CV_8UC1, cv::Scalar(255));
  const auto cell = [&](const Eigen::Vector2d& p) {
    return cv::Point(std::clamp(int(std::lround(p.x())) - roi.x, 0, roi.width - 1),
                     std::clamp(int(std::lround(p.y())) - roi.y, 0, roi.height - 1));
  };
  for (const Eigen::Vector2d& p : to) image.at<std::uint8_t>(cell(p)) = 0;
  cv::Mat distance;
  cv::distanceTransform(image, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  double sum = 0.0;
  for (const Eigen::Vector2d& p : from) sum += distance.at<float>(cell(p));
  return sum / double(from.size());
}

// H(A, B) = max(h_mod(A, B), h_mod(B, A)) (P3 eq. 9) of two sets of pixels of an image of `size`.
double Hausdorff(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b,
                 const cv::Size& size) {
  double min_u = size.width, min_v = size.height, max_u = 0.0, max_v = 0.0;
  for (const auto* set : {&a, &b}) {
    for (const Eigen::Vector2d& p : *set) {
      min_u = std::min(min_u, p.x());
      min_v = std::min(min_v, p.y());
      max_u = std::max(max_u, p.x());
      max_v = std::max(max_v, p.y());
    }
  }
  const int u0 = std::clamp(int(std::floor(min_u)) - 1, 0, size.width - 1);
  const int v0 = std::clamp(int(std::floor(min_v)) - 1, 0, size.height - 1);
  const int u1 = std::clamp(int(std::ceil(max_u)) + 1, u0, size.width - 1);
  const int v1 = std::clamp(int(std::ceil(max_v)) + 1, v0, size.height - 1);
  const cv::Rect roi(u0, v0, u1 - u0 + 1, v1 - v0 + 1);
  return std::max(ModifiedHausdorff(a, b, roi), ModifiedHausdorff(b, a, roi));
}

// The opening of a door hypothesis on the floor plan: column a at d1, column b at d1 + along,
// the tops at `height`; `normal` (unit) points from the columns' plane to the side the first
// view saw it from (the corridor). The plane `depth` behind it: normal . (x - d1) = -depth.
struct Opening {
  Eigen::Vector2d d1 = Eigen::Vector2d::Zero();
  Eigen::Vector2d along = Eigen::Vector2d::Zero();
  Eigen::Vector2d normal = Eigen::Vector2d::Zero();
  double height = 0.0;
  double margin = 0.0;  // of the opening left out at each side and at the top

  // The ray c + t r meets the plane `depth` behind the columns at t (P3 eq. 8); NaN when
  // parallel to it.
  double Meet(const Eigen::Vector3d& c, const Eigen::Vector3d& r, double depth) const {
    const double denominator = normal.dot(r.head<2>());
    if (std::abs(denominator) < 1e-9) return std::numeric_limits<double>::quiet_NaN();
    return -(normal.dot(c.head<2>() - d1) + depth) / denominator;
  }
  // Whether a point lies inside the opening (less the margins) seen along the plane's normal.
  bool Inside(const Eigen::Vector3d& p) const {
    const double s = (p.head<2>() - d1).dot(along) / along.squaredNorm();
    return s >= margin && s <= 1.0 - margin && p.z() >= 0.0 && p.z() <= height * (1.0 - margin);
  }
  // Whether a camera at c sees the point p (behind the columns, or a little in front of them)
  // through the opening: the line from c to p crosses the columns' plane inside it.
  bool SeenThrough(const Eigen::Vector3d& c, const Eigen::Vector3d& p) const {
    const double t = Meet(c, p - c, 0.0);
    return t > 0.0 && Inside(c + t * (p - c));
  }
  // The angle between the normal and the line from the opening's middle to a camera at c, on
  // the floor plan (0: straight in front of the door, pi/2: along its wall).
  double ViewAngle(const Eigen::Vector3d& c) const {
    const Eigen::Vector2d to_camera = c.head<2>() - (d1 + 0.5 * along);
    const double side = std::abs(to_camera.dot(along)) / along.norm();
    return std::atan2(side, std::abs(normal.dot(to_camera)));
  }
};
}  // namespace

struct UpwardDoorVerifier::Sighting {
  Eigen::Vector3d ray_a, ray_b;             // unit rays to the column tops, world frame
  double bearing_a = 0.0, bearing_b = 0.0;  // world bearings from the camera centre
  double elevation_a = 0.0, elevation_b = 0.0;
  double bar_coverage = 0.0;  // the candidate's
};

const OptionTable<DoorVerifierOptions>& DoorVerifierOptionsTable() {
  using O = DoorVerifierOptions;
  return StaticOptionTable<O>([](OptionTable<O>& t) {
    t.Add("particles", &O::particles, "", "samples per door candidate (P3: 200)").Range(10, 10000);
    t.AddEnum(
        "sensor_model", &O::sensor_model,
        {{"gaussian", DoorSensorModel::kGaussian}, {"triangular", DoorSensorModel::kTriangular}},
        "the particle filter's sensor model: gaussian (P3) or triangular (P2)");
    t.Add("bearing_error_rad", &O::bearing_error_rad, "rad",
          "theta error of a column's bearing: sigma, or the triangle's half-width")
        .Greater(0)
        .Range(0, 1);
    t.Add("elevation_error_rad", &O::elevation_error_rad, "rad",
          "alpha, beta errors of a column top's elevation")
        .Greater(0)
        .Range(0, 1);
    t.Add("min_top_height_m", &O::min_top_height_m, "m", "lowest column top of the prior")
        .Range(0, 100);
    t.Add("max_top_height_m", &O::max_top_height_m, "m", "highest column top of the prior")
        .Range(0, 100)
        .Note("> min_top_height_m");
    t.Add("min_door_top_m", &O::min_door_top_m, "m",
          "a converged candidate whose tops are lower is not a door")
        .Range(0, 100);
    t.Add("max_door_top_m", &O::max_door_top_m, "m", "nor one whose tops are higher")
        .Range(0, 100)
        .Note(">= min_door_top_m");
    t.Add("min_door_width_m", &O::min_door_width_m, "m",
          "a converged candidate whose columns are closer is not a door")
        .Range(0, 100);
    t.Add("max_door_width_m", &O::max_door_width_m, "m", "nor one whose columns are farther apart")
        .Range(0, 100)
        .Note(">= min_door_width_m");
    t.Add("min_median_bar_coverage", &O::min_median_bar_coverage, "",
          "a converged candidate whose bar covered less of the span between its columns in the "
          "median of its sightings is not a door")
        .Range(0, 1);
    t.Add("min_column_clearance_m", &O::min_column_clearance_m, "m",
          "a track with a column this close to where the robot has been is not a door")
        .Range(0, 100)
        .Note("< min_door_width_m / 2");
    t.Add("max_range_m", &O::max_range_m, "m", "columns drawn at most this far from the camera")
        .Greater(0)
        .Range(0, 1000);
    t.Add("roughening_m", &O::roughening_m, "m", "jitter of the samples after resampling")
        .Range(0, 10);
    t.Add("associate_rad", &O::associate_rad, "rad",
          "a candidate continues a track when each column lies within this of the interval of "
          "the track's samples' bearings (their central 95 %)")
        .Greater(0)
        .Range(0, 3.2);
    t.Add("converged_sigma_m", &O::converged_sigma_m, "m",
          "columns known to this (samples' standard deviation) are verified")
        .Greater(0)
        .Range(0, 100);
    t.Add("verify_baseline_m", &O::verify_baseline_m, "m",
          "camera travel between the plane's edge points and their comparison")
        .Greater(0)
        .Range(0, 100);
    t.Add("mhd_threshold_px", &O::mhd_threshold_px, "px",
          "Hausdorff distance of the prediction above which a candidate is open (P3 eq. 9)")
        .Greater(0)
        .Range(0, 10000);
    t.Add("min_leaf_depth_m", &O::min_leaf_depth_m, "m",
          "shallowest depth behind the columns' plane at which a closed surface is tried "
          "(negative: in front of it, a face flush with the edges paired; those depths can only "
          "close a candidate)")
        .Range(-1, 1);
    t.Add("max_leaf_depth_m", &O::max_leaf_depth_m, "m",
          "deepest depth behind the columns' plane at which a closed surface is tried (a leaf in "
          "the wall's thickness)")
        .Range(0, 1)
        .Note(">= min_leaf_depth_m");
    t.Add("leaf_depth_step_m", &O::leaf_depth_step_m, "m", "step between the leaf depths tried")
        .Greater(0)
        .Range(0, 1)
        .Note("at most 100 depths, one at or behind the columns");
    t.Add("opening_margin", &O::opening_margin, "",
          "fraction of the opening left out at each side (the frame's own edges)")
        .Range(0, 0.45);
    t.Add("min_edge_points", &O::min_edge_points, "", "fewer edge points: no decision yet")
        .Range(1, 100000);
    t.Add("sparse_max_view_angle_rad", &O::sparse_max_view_angle_rad, "rad",
          "a depth shared by fewer than min_edge_points (at least half) is ruled out, at twice "
          "the threshold, only when both views lie within this angle of the door's normal")
        .Range(0, 1.5708);
    t.Add("max_edge_points", &O::max_edge_points, "", "edge points kept on the plane at most")
        .Range(1, 1000000);
    t.Add("canny_low", &O::canny_low, "grey levels/px", "Canny's lower threshold").Range(0, 5000);
    t.Add("canny_high", &O::canny_high, "grey levels/px", "Canny's upper threshold")
        .Range(0, 5000)
        .Note(">= canny_low");
    t.Add("forget_after_frames", &O::forget_after_frames, "",
          "a track not seen for this many frames is dropped")
        .Range(1, 100000);
    t.Add("max_tracks", &O::max_tracks, "", "candidates followed at once at most").Range(1, 1000);
    t.Add("seed", &O::seed, "", "seed of the samples");
  });
}

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

void UpwardDoorVerifier::EdgesInOpening(const cv::Mat& edges, const SE3& world_from_camera,
                                        const Eigen::Vector4d& columns, double height,
                                        std::vector<Eigen::Vector2d>* pixels,
                                        std::vector<Eigen::Vector3d>* points) const {
  pixels->clear();
  points->clear();
  const Eigen::Vector3d c = world_from_camera.translation();
  const Eigen::Vector2d d1 = columns.head<2>(), d2 = columns.tail<2>();
  const Eigen::Vector2d along = d2 - d1;
  const double width = along.norm();
  if (!(width > 1e-3) || !(height > 0.0)) return;
  // P3 eq. 5: the plane's normal, the columns' direction turned by 90 degrees.
  const Eigen::Vector2d normal(-along.y() / width, along.x() / width);
  const double m = options_.opening_margin;
  // The opening's image: the bounding box of its outline's points that project.
  const Eigen::Matrix3d camera_from_world = world_from_camera.rotation().transpose();
  double min_u = edges.cols, min_v = edges.rows, max_u = -1, max_v = -1;
  for (int i = 0; i <= 10; ++i) {
    for (int j = 0; j <= 10; ++j) {
      const double s = m + (1.0 - 2.0 * m) * i / 10.0, z = height * (1.0 - m) * j / 10.0;
      const Eigen::Vector2d xy = d1 + s * along;
      const std::optional<Eigen::Vector2d> px =
          model_.Project(camera_from_world * (Eigen::Vector3d(xy.x(), xy.y(), z) - c));
      if (!px) continue;
      min_u = std::min(min_u, px->x());
      min_v = std::min(min_v, px->y());
      max_u = std::max(max_u, px->x());
      max_v = std::max(max_v, px->y());
    }
  }
  const int u0 = std::max(0, int(std::floor(min_u))), v0 = std::max(0, int(std::floor(min_v)));
  const int u1 = std::min(edges.cols - 1, int(std::ceil(max_u)));
  const int v1 = std::min(edges.rows - 1, int(std::ceil(max_v)));
  const Eigen::Matrix3d world_from_camera_r = world_from_camera.rotation();
  for (int v = v0; v <= v1; ++v) {
    const std::uint8_t* row = edges.ptr<std::uint8_t>(v);
    for (int u = u0; u <= u1; ++u) {
      if (!row[u]) continue;
      const Eigen::Vector2d px(u, v);
      const Eigen::Vector3d ray = world_from_camera_r * model_.Unproject(px);
      // P3 eq. 8: t = -(n . (c - D1)) / (n . d).
      const double denominator = normal.x() * ray.x() + normal.y() * ray.y();
      if (std::abs(denominator) < 1e-9) continue;
      const double t =
          -(normal.x() * (c.x() - d1.x()) + normal.y() * (c.y() - d1.y())) / denominator;
      if (!(t > 0.0)) continue;
      const Eigen::Vector3d p = c + t * ray;
      const double s = (p.head<2>() - d1).dot(along) / (width * width);
      if (s < m || s > 1.0 - m || p.z() < 0.0 || p.z() > height * (1.0 - m)) continue;
      pixels->push_back(px);
      points->push_back(p);
    }
  }
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

bool UpwardDoorVerifier::Test(Track* track, const cv::Mat& edges,
                              const SE3& world_from_camera) const {
  const Eigen::Vector3d c = world_from_camera.translation();
  const Eigen::Vector3d c0 = track->plane_view.translation();
  if ((c.head<2>() - c0.head<2>()).norm() < options_.verify_baseline_m) return false;
  // Free space: a column where the robot has been is no door's.
  const Eigen::Vector4d columns = Report(*track).columns;
  for (const Eigen::Vector2d& xy : path_) {
    if ((columns.head<2>() - xy).norm() < options_.min_column_clearance_m ||
        (columns.tail<2>() - xy).norm() < options_.min_column_clearance_m) {
      track->state = DoorTrackState::kClosed;
      return true;
    }
  }
  // The columns tested are the ones the plane was taken for: a track whose samples have moved
  // off them (a wrong pairing continuing it; later sightings refine them by a few centimetres)
  // or spread again is estimated again; one no longer of a door's size is not a door.
  const DoorTrackReport now = Report(*track);
  if ((now.columns - track->plane_columns).cwiseAbs().maxCoeff() >
          kMaxColumnShift * options_.converged_sigma_m ||
      std::sqrt(now.covariance.diagonal().maxCoeff()) > 2.0 * options_.converged_sigma_m) {
    Restart(track);
    return false;
  }
  if (!DoorSized(*track, now.columns, TopHeight(*track))) {
    track->state = DoorTrackState::kClosed;
    return true;
  }
  // The opening the plane's rays were taken through, its normal toward the first view.
  Opening opening;
  opening.d1 = track->plane_columns.head<2>();
  opening.along = track->plane_columns.tail<2>() - opening.d1;
  if (!(opening.along.norm() > 1e-3)) return false;
  opening.normal = Eigen::Vector2d(-opening.along.y(), opening.along.x()).normalized();
  if (opening.normal.dot(c0.head<2>() - opening.d1) < 0.0) opening.normal = -opening.normal;
  opening.height = track->plane_height;
  opening.margin = options_.opening_margin;

  // The edge pixels now inside the opening, and their rays.
  std::vector<Eigen::Vector2d> observed;
  std::vector<Eigen::Vector3d> on_plane;
  EdgesInOpening(edges, world_from_camera, track->plane_columns, track->plane_height, &observed,
                 &on_plane);
  const Eigen::Matrix3d camera_from_world = world_from_camera.rotation().transpose();
  const Eigen::Matrix3d first_from_world = track->plane_view.rotation().transpose();
  const cv::Size size(edges.cols, edges.rows);
  const auto in_first_image = [&](const Eigen::Vector3d& p) {
    const std::optional<Eigen::Vector2d> px = model_.Project(first_from_world * (p - c0));
    return px && model_.IsInImage(*px);
  };

  // P3 eq. 9 between the prediction A and the observation B, at each leaf depth, over what both
  // views saw through the opening. A depth at which A and B agree makes the door closed; one
  // at which they do not is ruled out for the rest of the test.
  const std::size_t depths = LeafDepths(options_);
  if (track->ruled_out_px.size() != depths) {
    track->ruled_out_px.assign(depths, std::numeric_limits<double>::quiet_NaN());
  }
  const bool sparse_may_rule_out = opening.ViewAngle(c0) <= options_.sparse_max_view_angle_rad &&
                                   opening.ViewAngle(c) <= options_.sparse_max_view_angle_rad;
  std::vector<Eigen::Vector2d> predicted, seen;
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_k = 0;
  for (std::size_t k = 0; k < depths; ++k) {
    const double depth = options_.min_leaf_depth_m + double(k) * options_.leaf_depth_step_m;
    predicted.clear();
    seen.clear();
    for (const Eigen::Vector3d& ray : track->plane_rays) {
      const double t = opening.Meet(c0, ray, depth);
      if (!(t > 0.0)) continue;
      const Eigen::Vector3d p = c0 + t * ray;
      if (!opening.Inside(p) || !opening.SeenThrough(c, p)) continue;
      const std::optional<Eigen::Vector2d> px = model_.Project(camera_from_world * (p - c));
      if (px && model_.IsInImage(*px)) predicted.push_back(*px);
    }
    for (std::size_t i = 0; i < observed.size(); ++i) {
      const Eigen::Vector3d ray = on_plane[i] - c;
      const double t = opening.Meet(c, ray, depth);
      if (!(t > 0.0)) continue;
      const Eigen::Vector3d p = c + t * ray;
      if (opening.Inside(p) && opening.SeenThrough(c0, p) && in_first_image(p)) {
        seen.push_back(observed[i]);
      }
    }
    // Too little seen by both views: this depth is neither confirmed nor ruled out now. H of
    // fewer points is noisier (closed doors seen with 37-54 points gave 5-7 px): with half
    // min_edge_points a depth can only be ruled out, at twice the threshold, and only from views
    // near the door's normal (from far off the jambs fill the opening). A depth in front of
    // the columns (a face flush with the edges paired) can close a candidate, never hold one
    // undecided: from the oblique view the plane was taken in, little of a plane in front falls
    // inside the opening, and the door would wait on it until it is out of view.
    const int shared = int(std::min(predicted.size(), seen.size()));
    if (2 * shared < options_.min_edge_points) continue;
    if (InFront(depth) && shared < options_.min_edge_points) continue;
    if (!sparse_may_rule_out && shared < options_.min_edge_points) continue;
    const double h = Hausdorff(predicted, seen, size);
    if (shared < options_.min_edge_points) {
      if (h > 2.0 * options_.mhd_threshold_px && !(h >= track->ruled_out_px[k])) {
        track->ruled_out_px[k] = h;
      }
      continue;
    }
    if (h < best) {
      best = h;
      best_k = k;
    }
    if (h > options_.mhd_threshold_px && !(h >= track->ruled_out_px[k])) {
      track->ruled_out_px[k] = h;
    }
  }
  if (best <= options_.mhd_threshold_px) {
    // A leaf at this depth explains what both views saw: closed.
    track->hausdorff_px = best;
    track->leaf_depth_m = options_.min_leaf_depth_m + double(best_k) * options_.leaf_depth_step_m;
    track->state = DoorTrackState::kClosed;
    return true;
  }
  // Open once every depth from the columns' plane back has been ruled out (in this frame or an
  // earlier one of the test): H is then the least of the distances that ruled them out.
  double least = std::numeric_limits<double>::infinity();
  std::size_t least_k = 0;
  for (std::size_t k = 0; k < depths; ++k) {
    if (InFront(options_.min_leaf_depth_m + double(k) * options_.leaf_depth_step_m)) continue;
    if (std::isnan(track->ruled_out_px[k])) return false;
    if (track->ruled_out_px[k] < least) {
      least = track->ruled_out_px[k];
      least_k = k;
    }
  }
  track->hausdorff_px = least;
  track->leaf_depth_m = options_.min_leaf_depth_m + double(least_k) * options_.leaf_depth_step_m;
  track->state = DoorTrackState::kOpen;
  return true;
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
