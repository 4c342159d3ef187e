#pragma once
// The `laser_slam` pipeline (docs/laser_slam.md): 2D laser SLAM with wheel odometry, as
// Cartographer's local SLAM does it (Hess et al., "Real-Time Loop Closure in 2D LIDAR SLAM",
// ICRA 2016, section IV) with one submap that covers the whole run: the odometry predicts the
// pose (P1 eqs. 13-17, with its covariance); each sweep, undistorted with the odometry
// (slam/laser/scan_points.h), is matched against the probability grid built so far with Ceres
// (slam/laser/scan_matcher.h: 1 - p per beam endpoint, priors towards the odometry prediction);
// the matched sweep is inserted into the grid when the robot has moved enough since the last
// insertion (Cartographer's motion filter). The match is fused with the odometry's prediction
// as a measurement with the sweep's point-to-line information (none along a featureless
// corridor: the odometry carries the estimate there); the reported covariance adds the grid's
// own error. The grid leaves as a PGM (maps/<name>.pgm).

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/options_table.h"
#include "common/wheel_odometry_model.h"
#include "slam/filter_support.h"
#include "slam/laser/probability_grid.h"
#include "slam/laser/scan_matcher.h"
#include "slam/laser/scan_points.h"
#include "slam/pipeline.h"

namespace corridorsim::slam {

/// Scenario key `pipelines.laser_slam` (the table in slam/pipeline_options.cpp).
struct LaserSlamOptions {
  double k_m = kDefaultWheelNoiseK_m;  // P1 eq. 17's k for the odometry's covariance
  std::string laser;                   // the scanner used ("" = the calibration's first)
  double max_range_m = 20.0;           // beams beyond are not used
  double match_interval_s = 0.1;       // sweeps closer than this to the last match are skipped
  int min_points = 30;                 // a sweep with fewer usable beams is not matched
  double point_spacing_m = 0.0;        // matched points keep this far apart (beam order)
  double resolution_m = 0.05;          // grid cell
  double hit_probability = 0.55;
  double miss_probability = 0.49;
  double max_map_extent_m = 200.0;
  double insert_distance_m = 0.2;  // motion filter: insert after this much travel ...
  double insert_angle_deg = 5.0;   // ... or this much turn
  double search_window_m = 0.05;   // correlative search: +- this in x and y (0: none)
  double search_window_deg = 1.0;  // ... +- this in heading
  double occupied_space_weight = 1.0;
  double translation_weight = 1.0;
  double rotation_weight = 1.0;
  int max_iterations = 20;
  double match_sigma_m = 0.05;  // the covariance model's point-to-line sigma
  double map_sigma_m = 0.025;   // the reported covariance adds the map's own error: position ...
  double map_sigma_deg = 0.3;   // ... and heading
  int normal_half_window = 3;   // neighbours each side that a point's normal is fitted to
  double normal_neighbourhood_m = 0.25;
  bool write_map = true;
  std::optional<OptionsProblem> Check() const;
};
/// The keys of `pipelines.laser_slam`.
const OptionTable<LaserSlamOptions>& LaserSlamOptionsTable();

class LaserSlamPipeline : public Pipeline {
 public:
  /// `calibration` must pass Check() and hold the scanner `options.laser` (any scanner when it
  /// is empty); else std::invalid_argument. It draws no random numbers (`seed` is unused).
  LaserSlamPipeline(const LaserSlamOptions& options, const Calibration& calibration,
                    std::uint64_t seed = 0);
  void Initialize(TimeNs stamp_ns, const SE2& world_from_robot) override;
  void OnOdometry(const WheelOdometry& odometry) override;
  void OnScan(const LaserScan& scan) override;
  PoseEstimate Estimate() const override;
  void Finish() override {}
  std::vector<MapFile> TakeMaps() override;
  std::map<std::string, double> stage_seconds() const override { return clock_.seconds(); }
  PipelineHealth health() const override { return health_; }

  /// What the sweeps held so far: beams dropped as REP 117's non-measurements (NaN, +-inf), and
  /// sweeps matched and inserted.
  std::int64_t non_finite_beams() const { return non_finite_beams_; }
  int matched_scans() const { return matched_scans_; }
  int inserted_scans() const { return inserted_scans_; }
  const laser::ProbabilityGrid& grid() const { return grid_; }

 private:
  // Why a sweep cannot be used (another scanner's, malformed, out of order), or nothing.
  std::optional<std::string> ScanProblem(const LaserScan& scan) const;

  LaserSlamOptions options_;
  double wheelbase_m_;
  LaserCalibration laser_;
  laser::ScanMatcherOptions matcher_;
  laser::CorrelativeSearchOptions search_;
  laser::ProbabilityGrid grid_;
  laser::OdometryTrack track_;
  SE2 odom_from_robot_;  // dead reckoning alone, for undistortion
  PoseEstimate estimate_;
  bool initialized_ = false;
  TimeNs last_scan_ns_ = -1;
  TimeNs last_match_ns_ = -1;
  std::optional<SE2> last_insert_pose_;
  std::int64_t non_finite_beams_ = 0;
  int matched_scans_ = 0;
  int inserted_scans_ = 0;
  PipelineHealth health_;
  StageClock clock_;
};

}  // namespace corridorsim::slam
