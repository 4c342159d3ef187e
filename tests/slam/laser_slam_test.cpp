// Tests slam/laser/ and slam/laser_slam_pipeline.cpp on synthetic sweeps of known 2D worlds (wall
// segments, ray cast here): the Ceres matcher brings a perturbed pose back to the true one in a
// room; in a featureless corridor the covariance model has no information along the axis and the
// pipeline keeps the odometry's along-track position while the walls correct the cross-track
// error and the heading; REP 117's non-measurements are dropped;
// the pipeline beats biased odometry in a room and writes its grid as a PGM.
#include "slam/laser_slam_pipeline.h"

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>

#include "slam/laser/probability_grid.h"
#include "slam/laser/scan_matcher.h"
#include "slam/laser/scan_points.h"
#include "tests/support/odometry_message.h"
#include "tests/support/pioneer_calibration.h"

namespace corridorsim::slam {
namespace {

using test::OdometryMessage;
constexpr double kPi = std::numbers::pi;

struct Segment {
  Eigen::Vector2d a, b;
};

// A rectangle's four walls.
std::vector<Segment> Box(double x0, double y0, double x1, double y1) {
  return {{{x0, y0}, {x1, y0}}, {{x1, y0}, {x1, y1}}, {{x1, y1}, {x0, y1}}, {{x0, y1}, {x0, y0}}};
}

// The range from `origin` along `angle` (world) to the nearest wall, +inf when none.
double CastRay(const std::vector<Segment>& walls, const Eigen::Vector2d& origin, double angle) {
  const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
  double best = std::numeric_limits<double>::infinity();
  for (const Segment& s : walls) {
    const Eigen::Vector2d e = s.b - s.a;
    const double denominator = d.x() * e.y() - d.y() * e.x();
    if (std::abs(denominator) < 1e-12) continue;
    const Eigen::Vector2d w = s.a - origin;
    const double t = (w.x() * e.y() - w.y() * e.x()) / denominator;
    const double u = (w.x() * d.y() - w.y() * d.x()) / denominator;
    if (t > 0 && u >= 0 && u <= 1) best = std::min(best, t);
  }
  return best;
}

// A 361-beam, 180 deg sweep of a level scanner at the robot's origin, all beams from one pose.
LaserScan Sweep(const std::vector<Segment>& walls, const SE2& world_from_robot, TimeNs stamp_ns,
                double max_range_m = 80.0) {
  LaserScan scan;
  scan.stamp_ns = stamp_ns;
  scan.sensor_id = "scanner";
  scan.angle_min_rad = -kPi / 2;
  scan.angle_increment_rad = kPi / 360;
  scan.time_increment_ns = 0;
  scan.scan_time_ns = 26'666'667;
  scan.range_min_m = 0.1;
  scan.range_max_m = max_range_m;
  for (int i = 0; i < 361; ++i) {
    const double angle = world_from_robot.yaw() + scan.angle_min_rad + i * scan.angle_increment_rad;
    const double r = CastRay(walls, world_from_robot.translation(), angle);
    scan.ranges_m.push_back(r <= max_range_m ? static_cast<float>(r)
                                             : std::numeric_limits<float>::infinity());
  }
  return scan;
}

// The sweep's endpoints in the robot frame (no motion: the track holds one pose).
std::vector<Eigen::Vector2d> PointsOf(const LaserScan& scan) {
  laser::OdometryTrack track(4);
  track.Add(scan.stamp_ns, SE2());
  return laser::ScanToPoints(scan, SE3(), track, scan.stamp_ns, 80.0).points;
}

// A grid built from exact sweeps at `poses`.
laser::ProbabilityGrid GridOf(const std::vector<Segment>& walls, const std::vector<SE2>& poses) {
  laser::ProbabilityGrid grid{laser::ProbabilityGridOptions{}};
  for (int repeat = 0; repeat < 5; ++repeat) {
    for (const SE2& pose : poses) {
      std::vector<Eigen::Vector2d> endpoints;
      for (const Eigen::Vector2d& p : PointsOf(Sweep(walls, pose, 0)))
        endpoints.push_back(pose * p);
      grid.InsertScan(pose.translation(), endpoints);
    }
  }
  return grid;
}

// A featureless corridor 2.4 m wide and 100 m long (no beam of a 20 m range meets an end wall).
std::vector<Segment> Corridor() { return {{{-50, -1.21}, {50, -1.21}}, {{-50, 1.19}, {50, 1.19}}}; }

// A room with a pillar: every pose direction is constrained. The walls lie off the 5 cm cell
// boundaries (a wall on a boundary splits its hits between two cells, a flat ridge).
std::vector<Segment> Room() {
  std::vector<Segment> walls = Box(-3.02, -2.01, 2.98, 1.99);
  const std::vector<Segment> pillar = Box(1.01, 0.81, 1.41, 1.21);
  walls.insert(walls.end(), pillar.begin(), pillar.end());
  return walls;
}

Calibration WithScanner() {
  Calibration calibration = test::PioneerCalibration();
  calibration.lasers.push_back(LaserCalibration{"scanner", SE3(), 37.5, 361, 0.01});
  return calibration;
}

TEST_CASE("a room's sweep matched from a perturbed pose converges to the true pose", "[laser]") {
  const std::vector<Segment> walls = Room();
  const SE2 truth(-0.5, -0.3, 0.3);
  const laser::ProbabilityGrid grid = GridOf(walls, {truth, SE2(0.5, 0.2, -0.4)});
  laser::ScanMatcherOptions options;
  options.translation_weight = 0.1;  // a weak prior: the grid alone decides
  options.rotation_weight = 0.1;
  // 10 cm and 2.3 deg off: the correlative search brings it into the bicubic cost's capture range.
  const SE2 prediction(truth.x() + 0.08, truth.y() - 0.06, truth.yaw() + 0.04);
  const std::vector<Eigen::Vector2d> points = PointsOf(Sweep(walls, truth, 0));
  const SE2 start = laser::CorrelativeSearch(grid, points, prediction, {});
  const laser::ScanMatchResult match = laser::MatchScan(grid, points, start, prediction, options);
  REQUIRE(match.usable);
  CHECK(match.final_cost <= match.initial_cost);
  // Within half a 5 cm cell and 0.3 deg.
  CHECK(std::hypot(match.world_from_robot.x() - truth.x(), match.world_from_robot.y() - truth.y()) <
        0.025);
  CHECK(std::abs(match.world_from_robot.yaw() - truth.yaw()) < 0.005);
}

TEST_CASE("in a featureless corridor the covariance model has no information along the axis",
          "[laser]") {
  // 2.4 m wide, 100 m long: with a 20 m range no beam meets an end wall.
  const std::vector<Segment> walls = Corridor();
  const SE2 truth(0.0, 0.3, 0.0);
  std::vector<Eigen::Vector2d> points;
  for (const Eigen::Vector2d& p : PointsOf(Sweep(walls, truth, 0))) {
    if (p.norm() < 20.0) points.push_back(p);
  }
  const std::vector<Eigen::Vector2d> normals = laser::ScanNormals(points, 3, 0.25);
  const Eigen::Matrix3d information = laser::ScanInformation(points, normals, truth, 0.05);
  CHECK(information(0, 0) < 1e-9 * information(1, 1));
  CHECK(information(1, 1) > 1e4);
  CHECK(information(2, 2) > 1e3);
  // In a room every direction has information.
  const std::vector<Eigen::Vector2d> room = PointsOf(Sweep(Room(), SE2(-0.5, -0.3, 0.3), 0));
  const Eigen::Matrix3d room_information =
      laser::ScanInformation(room, laser::ScanNormals(room, 3, 0.25), SE2(-0.5, -0.3, 0.3), 0.05);
  CHECK(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(room_information).eigenvalues().minCoeff() >
        1e3);
}

TEST_CASE("in a featureless corridor laser_slam keeps the odometry along the axis", "[laser]") {
  const std::vector<Segment> walls = Corridor();
  LaserSlamPipeline slam(LaserSlamOptions{}, WithScanner());
  const double b = test::PioneerCalibration().wheelbase_m;
  SE2 truth(-10.0, 0.3, 0.0);
  slam.Initialize(0, truth);
  SE2 dead_reckoning = truth;
  // 10 m straight in 500 steps of 20 ms; the odometry reads both wheels 3 % long and the left
  // one 0.5 % shorter than the right: it runs 0.3 m ahead and turns off the axis.
  for (int k = 1; k <= 500; ++k) {
    const double step = 0.02;
    truth = ApplyWheelOdometry(truth, step, step, b);
    const double left = 1.03 * 0.995 * step, right = 1.03 * step;
    dead_reckoning = ApplyWheelOdometry(dead_reckoning, left, right, b);
    slam.OnOdometry(OdometryMessage(TimeNs{k} * 20'000'000, left, right));
    slam.OnScan(Sweep(walls, truth, TimeNs{k} * 20'000'000));
  }
  const PoseEstimate e = slam.Estimate();
  // Along the axis the odometry's 3 % overshoot stays (0.3 m over 10 m; dead reckoning, which
  // turned off the axis, ran less far along it); across it and in heading the walls correct it.
  CHECK(dead_reckoning.x() - truth.x() > 0.2);
  CHECK(e.world_from_robot.x() - truth.x() == Approx(0.3).margin(0.03));
  CHECK(std::abs(dead_reckoning.y() - truth.y()) > 0.1);
  CHECK(std::abs(e.world_from_robot.y() - truth.y()) < 0.02);
  CHECK(std::abs(NormalizeAngle(e.world_from_robot.yaw() - truth.yaw())) < 0.005);
  CHECK(slam.matched_scans() > 40);
  // The covariance follows: the odometry's along the axis (var k s / 2 = 5e-4 m^2 over 10 m),
  // the grid's own (map_sigma_m^2) and next to nothing from the filter across it.
  const double map_variance = LaserSlamOptions{}.map_sigma_m * LaserSlamOptions{}.map_sigma_m;
  CHECK(e.covariance(0, 0) - map_variance == Approx(5e-4).epsilon(0.05));
  CHECK(e.covariance(1, 1) - map_variance < 1e-5);
}

TEST_CASE("REP 117's NaN and infinite ranges and ranges out of bounds are dropped", "[laser]") {
  LaserScan scan = Sweep(Room(), SE2(), 0);
  scan.ranges_m[0] = std::numeric_limits<float>::quiet_NaN();
  scan.ranges_m[1] = std::numeric_limits<float>::infinity();
  scan.ranges_m[2] = -std::numeric_limits<float>::infinity();
  scan.ranges_m[3] = 0.05f;   // below range_min
  scan.ranges_m[4] = 100.0f;  // above range_max
  laser::OdometryTrack track(4);
  track.Add(0, SE2());
  const laser::ScanPoints points = laser::ScanToPoints(scan, SE3(), track, 0, 80.0);
  CHECK(points.non_finite == 3);
  CHECK(points.out_of_range == 2);
  CHECK(points.points.size() == 356);
  for (const Eigen::Vector2d& p : points.points) CHECK(p.allFinite());
}

TEST_CASE("a sweep is undistorted with the odometry's motion during it", "[laser]") {
  // The robot drives at 1 m/s along x; beam i fires 10 ms after beam i - 1. A beam straight ahead
  // at range r fired at t lies at x = t + r in the world, so at x = t + r - t_ref seen from the
  // reference instant t_ref.
  laser::OdometryTrack track(16);
  for (int k = 0; k <= 10; ++k) track.Add(k * 100'000'000, SE2(0.1 * k, 0, 0));
  LaserScan scan;
  scan.stamp_ns = 0;
  scan.angle_min_rad = 0;
  scan.angle_increment_rad = 0;  // every beam straight ahead
  scan.time_increment_ns = 10'000'000;
  scan.scan_time_ns = 1'000'000'000;
  scan.range_min_m = 0.1;
  scan.range_max_m = 80;
  for (int i = 0; i < 50; ++i) scan.ranges_m.push_back(static_cast<float>(5.0 - 0.01 * i));
  const laser::ScanPoints points = laser::ScanToPoints(scan, SE3(), track, 1'000'000'000, 80.0);
  REQUIRE(points.points.size() == 50);
  for (const Eigen::Vector2d& p : points.points) {
    // The wall at x = 5 seen from x = 1.
    CHECK(p.x() == Approx(4.0).margin(1e-5));
    CHECK(p.y() == Approx(0.0).margin(1e-12));
  }
}

TEST_CASE("laser_slam corrects biased odometry in a room and maps it", "[laser]") {
  const std::vector<Segment> walls = Room();
  LaserSlamOptions options;
  options.match_interval_s = 0;
  LaserSlamPipeline slam(options, WithScanner());
  const double b = test::PioneerCalibration().wheelbase_m;
  SE2 truth(-2.0, -1.0, 0.0);
  slam.Initialize(0, truth);
  SE2 dead_reckoning = truth;
  // 300 steps of 20 ms along an arc; the odometry's left wheel reads 2 % short.
  for (int k = 1; k <= 300; ++k) {
    const double left = 0.006, right = 0.0064;
    truth = ApplyWheelOdometry(truth, left, right, b);
    const WheelOdometry odometry = OdometryMessage(TimeNs{k} * 20'000'000, 0.98 * left, right);
    dead_reckoning = ApplyWheelOdometry(dead_reckoning, 0.98 * left, right, b);
    slam.OnOdometry(odometry);
    slam.OnScan(Sweep(walls, truth, TimeNs{k} * 20'000'000));
  }
  const PoseEstimate e = slam.Estimate();
  const double slam_error = (e.world_from_robot.translation() - truth.translation()).norm();
  const double odometry_error = (dead_reckoning.translation() - truth.translation()).norm();
  CHECK(odometry_error > 0.1);
  CHECK(slam_error < 0.02);
  CHECK(std::abs(NormalizeAngle(e.world_from_robot.yaw() - truth.yaw())) < 0.005);
  CHECK(slam.matched_scans() == 299);  // the first sweep starts the grid
  CHECK(slam.inserted_scans() > 3);
  CHECK(slam.health().rejected_updates == 0);
  // The covariance is positive definite and small in a constrained room.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(e.covariance);
  CHECK(eigen.eigenvalues().minCoeff() > 0);
  CHECK(eigen.eigenvalues().maxCoeff() < 0.01);
  // The map: a PGM of the grid with its geometry in a comment.
  const std::vector<MapFile> maps = slam.TakeMaps();
  REQUIRE(maps.size() == 1);
  CHECK(maps[0].suffix == ".pgm");
  CHECK(maps[0].bytes.rfind("P5\n# resolution_m 0.050000 origin_m ", 0) == 0);
  const laser::ProbabilityGrid& grid = slam.grid();
  CHECK(grid.ProbabilityAt({2.98, 0.0}) > 0.6);  // a wall
  CHECK(grid.ProbabilityAt({0.0, 0.0}) < 0.5);   // free space
  CHECK(grid.ProbabilityAt({1.2, 1.0}) == 0.0);  // inside the pillar: never seen
}

TEST_CASE("laser_slam drops bad sweeps and keeps the odometry", "[laser]") {
  LaserSlamPipeline slam(LaserSlamOptions{}, WithScanner());
  slam.Initialize(0, SE2());
  slam.OnOdometry(OdometryMessage(20'000'000, 0.01, 0.01));
  LaserScan scan = Sweep(Room(), SE2(0.01, 0, 0), 20'000'000);
  for (float& r : scan.ranges_m) r = std::numeric_limits<float>::quiet_NaN();
  slam.OnScan(scan);
  CHECK(slam.non_finite_beams() == 361);
  CHECK(slam.health().rejected_updates == 1);
  CHECK(slam.Estimate().world_from_robot.x() == Approx(0.01));
  // Another scanner's sweep is not this pipeline's: ignored, not counted.
  scan.sensor_id = "other";
  slam.OnScan(scan);
  CHECK(slam.health().rejected_updates == 1);
  CHECK_THROWS_AS(LaserSlamPipeline(LaserSlamOptions{}, test::PioneerCalibration()),
                  std::invalid_argument);
}

TEST_CASE("laser_slam's options are bounded and checked across keys", "[laser]") {
  CHECK(!LaserSlamOptions{}.Check());
  LaserSlamOptions options;
  options.miss_probability = 0.5;
  options.hit_probability = 0.5;  // hit must exceed 0.5
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "hit_probability");
  options.hit_probability = 0.55;
  options.miss_probability = 0.55;  // above its bound [0.1, 0.5]
  CHECK(options.Check()->key == "miss_probability");
  options = LaserSlamOptions{};
  options.resolution_m = 0.01;  // 2 * 200 m / 1 cm = 40000 cells a side: 1.6e9 cells
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "max_map_extent_m");
  options = LaserSlamOptions{};
  options.search_window_m = 1.0;  // a correlative search of 41 x 41 cells per angle
  CHECK(options.Check()->key == "search_window_m");
}

}  // namespace
}  // namespace corridorsim::slam
