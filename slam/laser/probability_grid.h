#pragma once
// The occupancy grid laser_slam matches scans against and builds (docs/laser_slam.md): a 2D
// probability grid in the world frame, as Cartographer's ProbabilityGrid (Hess et al., "Real-Time
// Loop Closure in 2D LIDAR SLAM", ICRA 2016, section IV.B): each cell holds the probability that
// it is occupied, clamped to [kMinProbability, kMaxProbability]; a scan inserted at a pose marks
// its endpoints' cells as hits and the cells its beams cross as misses, each at most once per
// scan, by M_new = clamp(odds^-1(odds(M_old) * odds(p_hit or p_miss))) (the paper's eq. 2). A cell
// never observed is unknown. The grid grows (whole tiles of cells) as the robot explores, up to
// a bounded extent around the first scan.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace corridorsim::slam::laser {

/// Cartographer's probability clamps (mapping/probability_values.h).
inline constexpr double kMinProbability = 0.1;
inline constexpr double kMaxProbability = 0.9;

struct ProbabilityGridOptions {
  double resolution_m = 0.05;      // cell side
  double hit_probability = 0.55;   // p_hit of a beam's endpoint (Cartographer's default)
  double miss_probability = 0.49;  // p_miss of a cell a beam crosses (Cartographer's default)
  double max_extent_m = 500.0;     // the grid never reaches farther than this from its first cell
};

class ProbabilityGrid {
 public:
  explicit ProbabilityGrid(const ProbabilityGridOptions& options);

  /// Inserts one scan: `origin` the scanner's position and `endpoints` its beams' endpoints, in
  /// the world frame (m). Endpoints outside the bounded extent are dropped; the misses are the
  /// cells of the segment from the origin up to (not including) the endpoint's cell.
  void InsertScan(const Eigen::Vector2d& origin, const std::vector<Eigen::Vector2d>& endpoints);

  /// The correspondence cost 1 - p of cell (row, col) (row along y, col along x, from the
  /// grid's lower-left corner); kMaxCorrespondenceCost for unknown cells and outside the grid.
  double CorrespondenceCost(int row, int col) const;
  /// The probability of the cell containing `point` (world m); 0 when unknown.
  double ProbabilityAt(const Eigen::Vector2d& point) const;

  /// The grid coordinates (col, row) of a world point: cell centres sit at integers (the
  /// interpolator's convention); the cell containing `point` is (round(col), round(row)).
  Eigen::Vector2d GridCoordinates(const Eigen::Vector2d& point) const;

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  double resolution_m() const { return options_.resolution_m; }
  /// The world position of the lower-left corner of cell (0, 0).
  const Eigen::Vector2d& origin() const { return origin_; }
  bool empty() const { return rows_ == 0; }
  /// Cells ever observed.
  std::int64_t known_cells() const;

  /// The grid as a binary PGM (P5, 8 bits, rows from the top = largest y): 254 (1 - p), so 254
  /// free and 0 occupied, 205 unknown (ROS map_server's trinary convention); a comment line in
  /// the header gives the resolution and the world position of the lower-left corner, as ROS
  /// map_server's YAML `resolution` and `origin`.
  std::string ToPgm() const;

 private:
  // Makes the grid cover [lo, hi] (world m), clamped to the bounded extent.
  void Cover(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi);
  bool Contains(int row, int col) const {
    return row >= 0 && col >= 0 && row < rows_ && col < cols_;
  }
  void Update(int row, int col, double odds_factor);

  ProbabilityGridOptions options_;
  double hit_odds_, miss_odds_;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();  // lower-left corner of cell (0, 0)
  Eigen::Vector2d limit_lo_, limit_hi_;               // the bounded extent, set by the first scan
  int rows_ = 0, cols_ = 0;
  std::vector<float> probability_;      // row-major; 0 = unknown
  std::vector<std::uint32_t> updated_;  // the scan that last updated each cell
  std::uint32_t scan_count_ = 0;
};

/// The cost of an unknown cell (Cartographer's kMaxCorrespondenceCost).
inline constexpr double kMaxCorrespondenceCost = 1.0 - kMinProbability;

}  // namespace corridorsim::slam::laser
