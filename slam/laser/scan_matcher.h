#pragma once
// laser_slam's scan-to-map matcher (docs/laser_slam.md), Cartographer's Ceres scan matcher (Hess
// et al., "Real-Time Loop Closure in 2D LIDAR SLAM", ICRA 2016, section IV.C, eq. (CS);
// cartographer/mapping/internal/2d/scan_matching/ceres_scan_matcher_2d.cc): the pose xi that
// minimises
//   sum_k (w_occ / sqrt(K) * (1 - M_smooth(T_xi h_k)))^2
//     + (w_t * |t_xi - t_pred|)^2 + (w_r * (theta_xi - theta_pred))^2
// over the scan's K points h_k, M_smooth the grid's probabilities through ceres::
// BiCubicInterpolator, from the odometry prediction (its translation and rotation priors keep the
// estimate where the scan says nothing: along a featureless corridor). The covariance is a
// documented model rather than the solver's (the cost's Gauss-Newton Hessian vanishes where a
// point sits on the ridge of a wall): each point that lies on a locally straight piece of the
// scan constrains the pose along that line's normal n with standard deviation sigma, the
// point-to-line information J^T J / sigma^2 with J = [n^T, n^T (dR/dtheta) h_k] (Censi, "An
// accurate closed-form estimate of ICP's covariance", ICRA 2007, for point-to-line ICP).
//
// Ceres never appears in this header: corridorsim_slam links it privately (the SDK's installed
// headers must not need it).

#include <vector>

#include <Eigen/Core>

#include "common/pose.h"
#include "slam/laser/probability_grid.h"

namespace corridorsim::slam::laser {

struct ScanMatcherOptions {
  double occupied_space_weight = 1.0;  // w_occ (Cartographer's default)
  double translation_weight = 1.0;     // w_t (1/m)
  double rotation_weight = 1.0;        // w_r (1/rad)
  int max_iterations = 20;             // Ceres iterations per match
};

/// Cartographer's real-time correlative scan matcher (Olson, "Real-Time Correlative Scan
/// Matching", ICRA 2009; cartographer/mapping/internal/2d/scan_matching/
/// real_time_correlative_scan_matcher_2d.cc): every pose of a window around the prediction, on
/// the grid's cells in translation and in angular steps that move the farthest point by at most
/// a cell, scored by the mean probability of the cells its points fall in (unknown: 0) times
/// exp(-(w_t d)^2 - (w_r dtheta)^2); the best one seeds the Ceres match. It brings the pose into
/// the bicubic cost's capture range (a cell or two).
struct CorrelativeSearchOptions {
  double linear_window_m = 0.1;       // +- this in x and y (0: no search)
  double angular_window_rad = 0.035;  // +- this in heading
  double translation_weight = 1.0;    // w_t (1/m): the tie-breaker towards the prediction
  double rotation_weight = 1.0;       // w_r (1/rad)
};

/// The best pose of the correlative search around `prediction`.
SE2 CorrelativeSearch(const ProbabilityGrid& grid, const std::vector<Eigen::Vector2d>& points,
                      const SE2& prediction, const CorrelativeSearchOptions& options);

struct ScanMatchResult {
  SE2 world_from_robot;  // the matched pose
  bool usable = false;   // the solver reported a usable solution with a finite pose
  int iterations = 0;    // Ceres iterations taken
  double initial_cost = 0.0;
  double final_cost = 0.0;
};

/// Matches `points` (in the robot frame, m) against `grid` with Ceres from `start` (the
/// correlative search's result, or the prediction), its priors towards `prediction`
/// (world_from_robot), with one thread: the same inputs give the same bytes.
ScanMatchResult MatchScan(const ProbabilityGrid& grid, const std::vector<Eigen::Vector2d>& points,
                          const SE2& start, const SE2& prediction,
                          const ScanMatcherOptions& options);

/// The unit normals of the scan's locally straight pieces (robot frame): normal k belongs to
/// point k when the points within `neighbourhood_m` of it among its `half_window` neighbours on
/// either side (in beam order) number at least 3 and are collinear (the smaller eigenvalue of
/// their scatter below 1 % of the larger); else (0, 0).
std::vector<Eigen::Vector2d> ScanNormals(const std::vector<Eigen::Vector2d>& points,
                                         int half_window, double neighbourhood_m);

/// The point-to-line information of a scan at pose `world_from_robot` (3x3 over x, y, yaw): the
/// sum over the points with a normal of J^T J / sigma_m^2 (see above).
Eigen::Matrix3d ScanInformation(const std::vector<Eigen::Vector2d>& points,
                                const std::vector<Eigen::Vector2d>& normals,
                                const SE2& world_from_robot, double sigma_m);

}  // namespace corridorsim::slam::laser
