#pragma once
// An exact nearest-hit ray caster for near-horizontal rays: the planar laser scanner's (issue 53,
// sim/laser_scanner.h). The world's triangles are bucketed in a uniform 2D grid over their x-y
// footprint; a ray walks the cells its x-y track crosses, front to back (Amanatides and Woo, "A
// fast voxel traversal algorithm for ray tracing", Eurographics 1987), tests the triangles of each
// cell in 3D (Moller and Trumbore, "Fast, minimum storage ray/triangle intersection", JGT 1997)
// and stops at the first cell whose stretch of the ray holds a hit: a beam in a corridor crosses
// a few cells before it meets a wall, where a BVH walk visits every node along the whole ray.
//
// Each triangle's full test runs only in the cells where the ray meets the triangle's plane (and
// its z range), so a long wall triangle that lies in many cells is tested (about) once per ray.
// Level triangles (all three corners at one z: floor, ceiling, table tops), which would fill every
// cell they cover, are kept apart by their height: the ray meets height z at one point, so for
// each height within the ray's z range one cell (the one holding that point) is looked up, and a
// level beam, whose z range holds no height, pays nothing for them. The nearest such hit bounds
// the walk over the other triangles.
//
// A ray in a cell that is empty in its bands leaps over the empty square around the cell (the
// cells' distance to the nearest non-empty one, per band), so a beam down the corridor's middle
// costs a few steps, not one per cell.
//
// Exact: the hit is the nearest triangle the ray meets (a triangle admits hits up to 1e-12 of its
// barycentric range outside its edges, so that no ray slips between two triangles sharing an edge
// by rounding), whatever the cell size; the cells only cull.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace corridorsim::sim {

/// The nearest triangle a ray meets.
struct RayHit {
  double t = std::numeric_limits<double>::infinity();  // distance along the unit direction (m)
  int triangle = -1;                                   // its index; -1: nothing hit
};

class RayGrid {
 public:
  /// The side of a cell (m) unless the grid would have more than kMaxCells: a corridor 2.4 m wide
  /// spans three; bench_laser casts the most rays per second at 1 m of 0.25, 0.5, 1 and 2 m.
  static constexpr double kDefaultCellM = 1.0;
  /// The most cells (the side grows to keep a large world within it).
  static constexpr std::size_t kMaxCells = std::size_t{1} << 20;
  /// Each cell's triangles are listed per height band of this size (m), at most kMaxBands of them:
  /// a level beam reads one band's list, not the door frames' lintels or the plates above it.
  static constexpr double kBandM = 0.25;
  static constexpr int kMaxBands = 64;

  /// The triangles `corners` (three per triangle, world frame, m), in cells of side `cell_m` (> 0;
  /// larger if the world needs more than kMaxCells).
  explicit RayGrid(std::vector<Eigen::Vector3d> corners, double cell_m = kDefaultCellM);

  /// The nearest triangle that origin + t direction meets for t in (0, max_t]; `direction` has
  /// unit length. Safe to call from several threads.
  RayHit Nearest(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                 double max_t) const;

  int triangle_count() const { return static_cast<int>(triangles_.size()); }
  /// The triangle's corners in their given order, and (corner1 - corner0) x (corner2 - corner0).
  const Eigen::Vector3d& corner(int triangle, int k) const;
  const Eigen::Vector3d& normal(int triangle) const;
  double cell_m() const { return cell_m_; }
  int columns() const { return columns_; }
  int rows() const { return rows_; }
  /// The (list, triangle) pairs stored: each triangle once per cell its footprint meets (and, if
  /// not level, per height band of that cell its z range meets).
  std::size_t entries() const { return cell_triangles_.size() + level_triangles_.size(); }
  /// The distinct heights of the level triangles.
  std::size_t levels() const { return level_heights_.size(); }

 private:
  // One triangle, as Moller and Trumbore's test and the plane test read it.
  struct Triangle {
    Eigen::Vector3d v0, e1, e2;        // corner 0 and the edges to corners 1 and 2
    Eigen::Vector3d normal;            // e1 x e2
    Eigen::Vector3d unit_normal;       // normal / |normal| (0 for a degenerate triangle)
    double unit_plane = 0.0;           // unit_normal . v0 (m)
    Eigen::Vector3d box_min, box_max;  // the corners' bounding box, widened by the slack (m)
  };

  // Moller and Trumbore's test of triangle i: improves `best` if the ray meets it nearer.
  void Test(std::uint32_t i, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
            double max_t, RayHit* best) const;
  // The nearest level triangle the ray meets within (0, max_t] over [t0, t1] of its track.
  void NearestLevel(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t0,
                    double t1, double max_t, RayHit* best) const;
  // Builds one compressed-rows list of the triangles `is_member` selects, per cell and, with
  // `banded`, per height band of the cell.
  template <class Member>
  void BuildCells(Member&& is_member, bool banded, std::vector<std::uint32_t>* start,
                  std::vector<std::uint32_t>* triangles) const;
  // The height band holding z, clamped to the grid's.
  int BandOf(double z) const;

  // The triangles of cell (column, row) (their indices, ascending), through its first entry.
  std::size_t CellIndex(int column, int row) const {
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(columns_) +
           static_cast<std::size_t>(column);
  }

  std::vector<Eigen::Vector3d> corners_;
  std::vector<Triangle> triangles_;
  double cell_m_ = kDefaultCellM;
  Eigen::Vector2d min_ = Eigen::Vector2d::Zero();  // the grid's lower x-y corner (m)
  int columns_ = 0;                                // cells along x
  int rows_ = 0;                                   // cells along y
  double z_min_ = 0.0;                             // the lowest band's bottom (m)
  int bands_ = 1;                                  // height bands of kBandM
  // Compressed rows: list l holds the triangles [start[l], start[l + 1]); for the triangles that
  // are not level, list cell * bands_ + band; for those that are, list cell.
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> cell_triangles_;
  std::vector<std::uint32_t> level_start_;
  std::vector<std::uint32_t> level_triangles_;
  std::vector<double> level_heights_;  // ascending, distinct (m)
  // Per list of cell_start_: the chessboard distance (in cells) from the cell to the nearest one
  // with triangles in that band, at most 255; the cells nearer than it are empty in the band.
  std::vector<std::uint8_t> empty_radius_;
};

}  // namespace corridorsim::sim
