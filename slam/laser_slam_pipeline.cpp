#include "slam/laser_slam_pipeline.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace corridorsim::slam {
namespace {

// Odometry poses kept for undistortion: 64 messages, 1.3 s at 50 Hz, far more than a sweep lasts.
constexpr std::size_t kTrackCapacity = 64;

laser::ProbabilityGridOptions GridOptions(const LaserSlamOptions& o) {
  return {o.resolution_m, o.hit_probability, o.miss_probability, o.max_map_extent_m};
}

laser::ScanMatcherOptions MatcherOptions(const LaserSlamOptions& o) {
  return {o.occupied_space_weight, o.translation_weight, o.rotation_weight, o.max_iterations};
}

laser::CorrelativeSearchOptions SearchOptions(const LaserSlamOptions& o) {
  laser::CorrelativeSearchOptions search;
  search.linear_window_m = o.search_window_m;
  search.angular_window_rad = o.search_window_deg * std::numbers::pi / 180.0;
  return search;
}

LaserCalibration FindLaser(const Calibration& calibration, const std::string& id) {
  for (const LaserCalibration& l : calibration.lasers) {
    if (id.empty() || l.id == id) return l;
  }
  throw std::invalid_argument(
      id.empty() ? std::string("laser_slam needs a laser scanner (sensors: {<name>: {type: "
                               "laser}}) and the robot has none")
                 : "laser_slam: the robot has no laser scanner '" + id + "'");
}

// The match as a measurement of the pose with the point-to-line information I (slam/laser/
// scan_matcher.h), fused with the odometry's prediction (mean x_pred, covariance P) as a Kalman
// update in information form: K = (P^-1 + I)^-1 I = (1 + P I)^-1 P I, x = x_pred + K (x_match -
// x_pred), P' = (1 + P I)^-1 P (both hold for a singular P or I: a known start, a featureless
// corridor). Where the sweep constrains nothing (I's null space: along a featureless corridor)
// K is 0 and the odometry carries the estimate; where it constrains everything K tends to 1.
void FuseMatch(const SE2& match, const Eigen::Matrix3d& I, PoseEstimate* estimate) {
  const Eigen::Matrix3d& P = estimate->covariance;
  const Eigen::PartialPivLU<Eigen::Matrix3d> lu(Eigen::Matrix3d::Identity() + P * I);
  const Eigen::Matrix3d gain = lu.solve(P * I);
  const SE2& prediction = estimate->world_from_robot;
  const Eigen::Vector3d innovation(match.x() - prediction.x(), match.y() - prediction.y(),
                                   NormalizeAngle(match.yaw() - prediction.yaw()));
  const Eigen::Vector3d correction = gain * innovation;
  estimate->world_from_robot = SE2(prediction.x() + correction.x(), prediction.y() + correction.y(),
                                   prediction.yaw() + correction.z());
  const Eigen::Matrix3d updated = lu.solve(P);
  estimate->covariance = 0.5 * (updated + updated.transpose());
}

// The points the matcher uses: in beam order, each at least `spacing_m` from the last one kept
// (a sweep's near wall holds a point every centimetre; the matcher's cost and the covariance
// model's information then count stretches of wall rather than beams).
std::vector<Eigen::Vector2d> Thinned(const std::vector<Eigen::Vector2d>& points, double spacing_m) {
  std::vector<Eigen::Vector2d> kept;
  for (const Eigen::Vector2d& p : points) {
    if (kept.empty() || (p - kept.back()).squaredNorm() >= spacing_m * spacing_m) kept.push_back(p);
  }
  return kept;
}

}  // namespace

std::optional<OptionsProblem> LaserSlamOptions::Check() const {
  if (auto problem = CheckOptionBounds(LaserSlamOptionsTable(), *this)) return problem;
  if (miss_probability >= hit_probability) {
    return OptionsProblem{"miss_probability", "must be below hit_probability"};
  }
  // The grid's cells, (2 max_map_extent_m / resolution_m)^2 at most, stay below 2^28 (a GiB
  // of floats and update markers).
  const double side = 2.0 * max_map_extent_m / resolution_m;
  if (side * side > static_cast<double>(1 << 28)) {
    return OptionsProblem{"max_map_extent_m",
                          "(2 max_map_extent_m / resolution_m)^2 cells must stay below 2^28"};
  }
  return std::nullopt;
}

LaserSlamPipeline::LaserSlamPipeline(const LaserSlamOptions& options,
                                     const Calibration& calibration, std::uint64_t /*seed*/)
    : options_(options),
      wheelbase_m_(calibration.wheelbase_m),
      laser_(FindLaser(calibration, options.laser)),
      matcher_(MatcherOptions(options)),
      search_(SearchOptions(options)),
      grid_(GridOptions(options)),
      track_(kTrackCapacity) {
  CheckOrDie(!calibration.Check(), "slam::LaserSlamPipeline", "the calibration fails its Check()");
  CheckOrDie(!options.Check(), "slam::LaserSlamPipeline", "the options fail their Check()");
}

void LaserSlamPipeline::Initialize(TimeNs stamp_ns, const SE2& world_from_robot) {
  estimate_.stamp_ns = stamp_ns;
  estimate_.world_from_robot = world_from_robot;
  estimate_.covariance.setZero();  // the start pose is known exactly
  odom_from_robot_ = SE2::Identity();
  track_ = laser::OdometryTrack(kTrackCapacity);
  track_.Add(stamp_ns, odom_from_robot_);
  initialized_ = true;
}

void LaserSlamPipeline::OnOdometry(const WheelOdometry& odometry) {
  if (!initialized_ || OdometryProblem(odometry, estimate_.stamp_ns)) {
    ++health_.rejected_odometry;
    return;
  }
  const auto t0 = StageClock::Clock::now();
  const double left = odometry.left_distance_m, right = odometry.right_distance_m;
  Eigen::Matrix3d F;
  Eigen::Matrix<double, 3, 2> G;
  // P1 eqs. 13-17: the prediction and its covariance P = F P F^T + G Q G^T.
  estimate_.world_from_robot =
      ApplyWheelOdometry(estimate_.world_from_robot, left, right, wheelbase_m_, &F, &G);
  const Eigen::Matrix3d P = F * estimate_.covariance * F.transpose() +
                            G * WheelOdometryNoise(left, right, options_.k_m) * G.transpose();
  estimate_.covariance = 0.5 * (P + P.transpose());
  estimate_.stamp_ns = odometry.stamp_ns;
  odom_from_robot_ = ApplyWheelOdometry(odom_from_robot_, left, right, wheelbase_m_);
  track_.Add(odometry.stamp_ns, odom_from_robot_);
  clock_.Add("predict", StageClock::SecondsSince(t0));
}

std::optional<std::string> LaserSlamPipeline::ScanProblem(const LaserScan& scan) const {
  if (scan.ranges_m.empty()) return "no beams";
  if (!std::isfinite(scan.angle_min_rad) || !std::isfinite(scan.angle_increment_rad) ||
      !std::isfinite(scan.range_min_m) || !std::isfinite(scan.range_max_m) ||
      scan.time_increment_ns < 0 || scan.scan_time_ns < 0) {
    return "a malformed geometry";
  }
  if (scan.stamp_ns <= last_scan_ns_) return "out of time order";
  return std::nullopt;
}

void LaserSlamPipeline::OnScan(const LaserScan& scan) {
  if (scan.sensor_id != laser_.id) return;  // another scanner's sweep
  if (!initialized_ || ScanProblem(scan)) {
    ++health_.rejected_updates;
    return;
  }
  last_scan_ns_ = scan.stamp_ns;
  // The sweep is matched at the latest odometry stamp, the estimate's: the pose every beam is
  // brought to.
  const TimeNs reference_ns = estimate_.stamp_ns;
  const auto interval_ns = static_cast<TimeNs>(std::llround(options_.match_interval_s * 1e9));
  if (last_match_ns_ >= 0 && reference_ns - last_match_ns_ < interval_ns) return;
  const auto t0 = StageClock::Clock::now();
  const laser::ScanPoints scan_points = laser::ScanToPoints(scan, laser_.robot_from_laser, track_,
                                                            reference_ns, options_.max_range_m);
  non_finite_beams_ += scan_points.non_finite;
  const std::vector<Eigen::Vector2d>& points = scan_points.points;
  clock_.Add("points", StageClock::SecondsSince(t0));
  if (static_cast<int>(points.size()) < options_.min_points) {
    ++health_.rejected_updates;
    return;
  }
  last_match_ns_ = reference_ns;
  if (!grid_.empty()) {
    const auto t1 = StageClock::Clock::now();
    const SE2& prediction = estimate_.world_from_robot;
    const std::vector<Eigen::Vector2d> matched = Thinned(points, options_.point_spacing_m);
    const SE2 start = laser::CorrelativeSearch(grid_, matched, prediction, search_);
    const laser::ScanMatchResult match =
        laser::MatchScan(grid_, matched, start, prediction, matcher_);
    clock_.Add("match", StageClock::SecondsSince(t1));
    if (!match.usable) {
      ++health_.rejected_updates;
      return;
    }
    const auto t2 = StageClock::Clock::now();
    const std::vector<Eigen::Vector2d> normals =
        laser::ScanNormals(points, options_.normal_half_window, options_.normal_neighbourhood_m);
    const Eigen::Matrix3d information =
        laser::ScanInformation(points, normals, match.world_from_robot, options_.match_sigma_m);
    FuseMatch(match.world_from_robot, information, &estimate_);
    ++matched_scans_;
    clock_.Add("covariance", StageClock::SecondsSince(t2));
  }
  // Cartographer's motion filter: insert after enough travel or turn since the last insertion.
  const SE2& pose = estimate_.world_from_robot;
  if (last_insert_pose_) {
    const SE2 moved = last_insert_pose_->Inverse() * pose;
    if (moved.translation().norm() < options_.insert_distance_m &&
        std::abs(moved.yaw()) < options_.insert_angle_deg * std::numbers::pi / 180.0) {
      return;
    }
  }
  const auto t3 = StageClock::Clock::now();
  std::vector<Eigen::Vector2d> endpoints;
  endpoints.reserve(points.size());
  for (const Eigen::Vector2d& p : points) endpoints.push_back(pose * p);
  const Eigen::Vector2d origin = pose * laser_.robot_from_laser.translation().head<2>();
  grid_.InsertScan(origin, endpoints);
  last_insert_pose_ = pose;
  ++inserted_scans_;
  clock_.Add("insert", StageClock::SecondsSince(t3));
}

PoseEstimate LaserSlamPipeline::Estimate() const {
  // The filter's covariance is relative to the grid, which carries errors of its own (a wall's
  // ridge sits at the centre of the cells its hits fall in: up to half a cell off; the heading it
  // was built at): the reported covariance adds them, once a sweep has been matched.
  PoseEstimate estimate = estimate_;
  if (matched_scans_ > 0) {
    const double yaw_sigma = options_.map_sigma_deg * std::numbers::pi / 180.0;
    estimate.covariance +=
        Eigen::Vector3d(options_.map_sigma_m * options_.map_sigma_m,
                        options_.map_sigma_m * options_.map_sigma_m, yaw_sigma * yaw_sigma)
            .asDiagonal();
  }
  return estimate;
}

std::vector<MapFile> LaserSlamPipeline::TakeMaps() {
  if (!options_.write_map || grid_.empty()) return {};
  return {MapFile{".pgm", grid_.ToPgm()}};
}

}  // namespace corridorsim::slam
