#include "sim/ray_grid.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>

#include "common/error.h"

namespace corridorsim::sim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// How far a triangle's footprint, and the stretch of a ray a cell holds, are widened (m): the cell
// boundaries' rounding is ~1e-13 m, so a hit on a boundary is found in the cells on both sides.
constexpr double kSlackM = 1e-6;
// Hits up to this fraction of a triangle's barycentric range outside its edges count (rounding
// alone must not let a ray slip between two triangles sharing an edge).
constexpr double kWatertight = 1e-12;
// |(corner1 - corner0) x (corner2 - corner0) . direction| below this (m^2): the ray runs in the
// triangle's plane, no hit.
constexpr double kParallelM2 = 1e-14;
// The plane test culls a triangle only when the ray meets its plane at more than ~0.06 deg
// (|unit normal . direction|), where that distance is good to ~1e-10 m; nearer the plane it could
// be off by more than kSlackM, and the full test decides.
constexpr double kPlaneCullMinCos = 1e-3;

// Whether the triangle a, b, c (x-y) meets the axis-aligned rectangle centre +- half: separating
// axes (the rectangle's two, implied by the caller's bounding-box overlap, and the triangle's
// three edge normals); a triangle seen edge-on (a segment) is handled by the same axes.
bool TriangleMeetsRectangle(const Eigen::Vector2d (&corner)[3], const Eigen::Vector2d& centre,
                            const Eigen::Vector2d& half) {
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d edge = corner[(k + 1) % 3] - corner[k];
    const Eigen::Vector2d axis(-edge.y(), edge.x());
    const double on_edge = axis.dot(corner[k]), opposite = axis.dot(corner[(k + 2) % 3]);
    const double reach = std::abs(axis.x()) * half.x() + std::abs(axis.y()) * half.y();
    const double middle = axis.dot(centre);
    if (middle + reach < std::min(on_edge, opposite) ||
        middle - reach > std::max(on_edge, opposite)) {
      return false;
    }
  }
  return true;
}

}  // namespace

RayGrid::RayGrid(std::vector<Eigen::Vector3d> corners, double cell_m)
    : corners_(std::move(corners)), cell_m_(cell_m) {
  CheckOrDie(corners_.size() % 3 == 0, "RayGrid", "three corners per triangle");
  CheckOrDie(cell_m > 0 && std::isfinite(cell_m), "RayGrid", "the cell side must be positive");
  CheckOrDie(corners_.size() / 3 < std::numeric_limits<std::uint32_t>::max(), "RayGrid",
             "too many triangles");
  if (corners_.empty()) return;  // nothing to hit
  Eigen::Vector2d lo = corners_.front().head<2>(), hi = lo;
  for (const Eigen::Vector3d& c : corners_) {
    CheckOrDie(c.allFinite(), "RayGrid", "a corner is not finite");
    lo = lo.cwiseMin(c.head<2>());
    hi = hi.cwiseMax(c.head<2>());
  }
  min_ = lo - Eigen::Vector2d::Constant(2 * kSlackM);
  const Eigen::Vector2d extent = hi - lo + Eigen::Vector2d::Constant(4 * kSlackM);
  auto cells_along = [&](double length) { return std::max(1.0, std::ceil(length / cell_m_)); };
  while (cells_along(extent.x()) * cells_along(extent.y()) > static_cast<double>(kMaxCells)) {
    cell_m_ *= 1.25;
  }
  columns_ = static_cast<int>(cells_along(extent.x()));
  rows_ = static_cast<int>(cells_along(extent.y()));
  double z_lo = corners_.front().z(), z_hi = z_lo;
  for (const Eigen::Vector3d& c : corners_) {
    z_lo = std::min(z_lo, c.z());
    z_hi = std::max(z_hi, c.z());
  }
  z_min_ = z_lo - 2 * kSlackM;
  bands_ = static_cast<int>(std::clamp(std::ceil((z_hi - z_lo + 4 * kSlackM) / kBandM), 1.0,
                                       static_cast<double>(kMaxBands)));

  triangles_.resize(corners_.size() / 3);
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    Triangle& t = triangles_[i];
    const Eigen::Vector3d* v = &corners_[3 * i];
    t.v0 = v[0];
    t.e1 = v[1] - v[0];
    t.e2 = v[2] - v[0];
    t.normal = t.e1.cross(t.e2);
    const double length = t.normal.norm();
    t.unit_normal = length > 0 ? Eigen::Vector3d(t.normal / length) : Eigen::Vector3d::Zero();
    t.unit_plane = t.unit_normal.dot(t.v0);
    t.box_min = v[0].cwiseMin(v[1]).cwiseMin(v[2]) - Eigen::Vector3d::Constant(kSlackM);
    t.box_max = v[0].cwiseMax(v[1]).cwiseMax(v[2]) + Eigen::Vector3d::Constant(kSlackM);
  }

  // The level triangles' heights; the others go in the walk's cells.
  auto is_level = [&](std::size_t i) {
    const Eigen::Vector3d* v = &corners_[3 * i];
    return v[0].z() == v[1].z() && v[1].z() == v[2].z();
  };
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    if (is_level(i)) level_heights_.push_back(corners_[3 * i].z());
  }
  std::sort(level_heights_.begin(), level_heights_.end());
  level_heights_.erase(std::unique(level_heights_.begin(), level_heights_.end()),
                       level_heights_.end());
  BuildCells([&](std::size_t i) { return !is_level(i); }, true, &cell_start_, &cell_triangles_);
  BuildCells(is_level, false, &level_start_, &level_triangles_);

  // Per band, each cell's chessboard distance to the nearest cell with triangles in that band (0:
  // its own; capped at 255), by the two-pass transform of Rosenfeld and Pfaltz ("Sequential
  // operations in digital picture processing", JACM 1966): a ray in an empty cell leaps the
  // empty square around it.
  empty_radius_.assign(cell_start_.size() - 1, 255);
  auto at = [&](int c, int r, int b) -> std::uint8_t& {
    return empty_radius_[CellIndex(c, r) * static_cast<std::size_t>(bands_) +
                         static_cast<std::size_t>(b)];
  };
  auto relax = [&](int c, int r, int b, int dc, int dr) {
    const int nc = c + dc, nr = r + dr;
    if (nc < 0 || nc >= columns_ || nr < 0 || nr >= rows_) return;
    at(c, r, b) = static_cast<std::uint8_t>(std::min(at(c, r, b) + 0, at(nc, nr, b) + 1));
  };
  for (int b = 0; b < bands_; ++b) {
    for (int r = 0; r < rows_; ++r) {
      for (int c = 0; c < columns_; ++c) {
        const std::size_t list =
            CellIndex(c, r) * static_cast<std::size_t>(bands_) + static_cast<std::size_t>(b);
        if (cell_start_[list] != cell_start_[list + 1]) at(c, r, b) = 0;
      }
    }
    for (int r = 0; r < rows_; ++r) {
      for (int c = 0; c < columns_; ++c) {
        for (const auto& [dc, dr] : {std::pair{-1, 0}, {-1, -1}, {0, -1}, {1, -1}}) {
          relax(c, r, b, dc, dr);
        }
      }
    }
    for (int r = rows_ - 1; r >= 0; --r) {
      for (int c = columns_ - 1; c >= 0; --c) {
        for (const auto& [dc, dr] : {std::pair{1, 0}, {1, 1}, {0, 1}, {-1, 1}}) {
          relax(c, r, b, dc, dr);
        }
      }
    }
  }
}

int RayGrid::BandOf(double z) const {
  const double band = std::floor((z - z_min_) / kBandM);
  return static_cast<int>(std::clamp(band, 0.0, bands_ - 1.0));
}

template <class Member>
void RayGrid::BuildCells(Member&& is_member, bool banded, std::vector<std::uint32_t>* start,
                         std::vector<std::uint32_t>* triangles) const {
  // Calls `visit(list)` for each cell that triangle i's footprint (widened by kSlackM) meets, in
  // each band its z range (widened) meets.
  const Eigen::Vector2d half = Eigen::Vector2d::Constant(0.5 * cell_m_ + kSlackM);
  auto for_each_cell = [&](std::size_t i, auto&& visit) {
    const Eigen::Vector2d footprint[3] = {corners_[3 * i].head<2>(), corners_[3 * i + 1].head<2>(),
                                          corners_[3 * i + 2].head<2>()};
    const Eigen::Vector2d box_lo = footprint[0].cwiseMin(footprint[1]).cwiseMin(footprint[2]);
    const Eigen::Vector2d box_hi = footprint[0].cwiseMax(footprint[1]).cwiseMax(footprint[2]);
    auto first_last = [&](int axis, int count) {
      const double from = std::floor((box_lo[axis] - kSlackM - min_[axis]) / cell_m_);
      const double to = std::floor((box_hi[axis] + kSlackM - min_[axis]) / cell_m_);
      return std::pair{static_cast<int>(std::clamp(from, 0.0, count - 1.0)),
                       static_cast<int>(std::clamp(to, 0.0, count - 1.0))};
    };
    const auto [c0, c1] = first_last(0, columns_);
    const auto [r0, r1] = first_last(1, rows_);
    const int b0 = banded ? BandOf(triangles_[i].box_min.z()) : 0;
    const int b1 = banded ? BandOf(triangles_[i].box_max.z()) : 0;
    const std::size_t per_cell = banded ? static_cast<std::size_t>(bands_) : 1;
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        const Eigen::Vector2d centre = min_ + cell_m_ * Eigen::Vector2d(c + 0.5, r + 0.5);
        if (!TriangleMeetsRectangle(footprint, centre, half)) continue;
        for (int b = b0; b <= b1; ++b)
          visit(CellIndex(c, r) * per_cell + static_cast<std::size_t>(b));
      }
    }
  };
  // Count per list, prefix sums, then fill in triangle order (ascending).
  start->assign(static_cast<std::size_t>(columns_) * static_cast<std::size_t>(rows_) *
                        (banded ? static_cast<std::size_t>(bands_) : 1) +
                    1,
                0);
  std::size_t total = 0;
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    if (!is_member(i)) continue;
    for_each_cell(i, [&](std::size_t cell) {
      ++(*start)[cell + 1];
      ++total;
    });
  }
  CheckOrDie(total < std::numeric_limits<std::uint32_t>::max(), "RayGrid",
             "too many (cell, triangle) pairs");
  for (std::size_t c = 1; c < start->size(); ++c) (*start)[c] += (*start)[c - 1];
  triangles->resize(total);
  std::vector<std::uint32_t> fill(start->begin(), start->end() - 1);
  for (std::size_t i = 0; i < triangles_.size(); ++i) {
    if (!is_member(i)) continue;
    for_each_cell(
        i, [&](std::size_t cell) { (*triangles)[fill[cell]++] = static_cast<std::uint32_t>(i); });
  }
}

const Eigen::Vector3d& RayGrid::corner(int triangle, int k) const {
  return corners_[3 * static_cast<std::size_t>(triangle) + static_cast<std::size_t>(k)];
}

const Eigen::Vector3d& RayGrid::normal(int triangle) const {
  return triangles_[static_cast<std::size_t>(triangle)].normal;
}

void RayGrid::Test(std::uint32_t i, const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                   double max_t, RayHit* best) const {
  // Moller and Trumbore (1997), both faces.
  const Triangle& tri = triangles_[i];
  const Eigen::Vector3d p = direction.cross(tri.e2);
  const double det = tri.e1.dot(p);
  if (std::abs(det) < kParallelM2) return;
  const double inv = 1.0 / det;
  const Eigen::Vector3d s = origin - tri.v0;
  const double u = s.dot(p) * inv;
  if (u < -kWatertight || u > 1.0 + kWatertight) return;
  const Eigen::Vector3d q = s.cross(tri.e1);
  const double v = direction.dot(q) * inv;
  if (v < -kWatertight || u + v > 1.0 + kWatertight) return;
  const double t = tri.e2.dot(q) * inv;
  if (t > 0.0 && t <= max_t && t < best->t) *best = {t, static_cast<int>(i)};
}

void RayGrid::NearestLevel(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                           double t0, double t1, double max_t, RayHit* best) const {
  if (direction.z() == 0.0) return;  // parallel to every level triangle
  const double z0 = origin.z() + t0 * direction.z(), z1 = origin.z() + t1 * direction.z();
  auto height =
      std::lower_bound(level_heights_.begin(), level_heights_.end(), std::min(z0, z1) - kSlackM);
  for (; height != level_heights_.end() && *height <= std::max(z0, z1) + kSlackM; ++height) {
    // Where the ray meets this height: the cell holding that point holds every level triangle
    // there that the ray can meet (their footprints are widened by kSlackM).
    const double t = (*height - origin.z()) / direction.z();
    if (!(t > -kSlackM && t <= max_t + kSlackM && t < best->t + kSlackM)) continue;
    int cell[2];
    bool inside = true;
    for (int a = 0; a < 2; ++a) {
      const double at = std::floor((origin[a] + t * direction[a] - min_[a]) / cell_m_);
      inside = inside && at >= 0 && at < (a == 0 ? columns_ : rows_);
      cell[a] = inside ? static_cast<int>(at) : 0;
    }
    if (!inside) continue;
    const std::size_t c = CellIndex(cell[0], cell[1]);
    for (std::uint32_t e = level_start_[c]; e < level_start_[c + 1]; ++e) {
      const std::uint32_t i = level_triangles_[e];
      if (triangles_[i].v0.z() == *height) Test(i, origin, direction, max_t, best);
    }
  }
}

RayHit RayGrid::Nearest(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                        double max_t) const {
  RayHit best;
  if (triangles_.empty() || !(max_t > 0)) return best;
  // The stretch [t0, t1] of the ray over the grid's rectangle (slabs).
  const int count[2] = {columns_, rows_};
  int step[2];
  double inverse[2];
  double t0 = 0.0, t1 = max_t;
  for (int a = 0; a < 2; ++a) {
    step[a] = direction[a] > 0 ? 1 : direction[a] < 0 ? -1 : 0;
    inverse[a] = step[a] == 0 ? 0.0 : 1.0 / direction[a];
    // Where the ray crosses the grid's two sides across this axis (none when parallel to them).
    const double side_lo = min_[a], side_hi = min_[a] + count[a] * cell_m_;
    if (step[a] == 0 && (origin[a] < side_lo || origin[a] > side_hi)) return best;
    if (step[a] == 0) continue;
    const double cross_lo = (side_lo - origin[a]) * inverse[a];
    const double cross_hi = (side_hi - origin[a]) * inverse[a];
    t0 = std::max(t0, std::min(cross_lo, cross_hi));
    t1 = std::min(t1, std::max(cross_lo, cross_hi));
  }
  if (!(t0 <= t1)) return best;
  NearestLevel(origin, direction, t0, t1, max_t, &best);
  t1 = std::min(t1, best.t);  // the walk ends at the nearest level hit

  // Amanatides and Woo's walk: the cell at t0, and per axis the step and the next boundary's t
  // (recomputed from the cell index each step, so no error accumulates).
  int cell[2];
  double next[2];
  for (int a = 0; a < 2; ++a) {
    const double at = (origin[a] + t0 * direction[a] - min_[a]) / cell_m_;
    cell[a] = static_cast<int>(std::clamp(std::floor(at), 0.0, count[a] - 1.0));
  }
  auto boundary = [&](int a) {
    if (step[a] == 0) return kInf;
    const int edge = cell[a] + (step[a] > 0 ? 1 : 0);
    return (min_[a] + edge * cell_m_ - origin[a]) * inverse[a];
  };
  next[0] = boundary(0);
  next[1] = boundary(1);

  double enter = t0;
  while (true) {
    const double exit = std::min({next[0], next[1], t1});
    // This cell holds the ray over [enter, exit]: its z range there culls the triangles whose z
    // range it misses, the plane test those whose plane it meets elsewhere.
    const double lo = enter - kSlackM, hi = exit + kSlackM;
    const double z_enter = origin.z() + enter * direction.z();
    const double z_exit = origin.z() + exit * direction.z();
    const double z_lo = std::min(z_enter, z_exit) - kSlackM;
    const double z_hi = std::max(z_enter, z_exit) + kSlackM;
    // The bands the ray's z range meets (a triangle in several is tested again, to no effect).
    const int band_lo = BandOf(z_lo), band_hi = BandOf(z_hi);
    const std::size_t first = CellIndex(cell[0], cell[1]) * static_cast<std::size_t>(bands_);
    const std::size_t from = first + static_cast<std::size_t>(band_lo);
    const std::size_t to = first + static_cast<std::size_t>(band_hi) + 1;
    if (cell_start_[from] == cell_start_[to]) {
      // Nothing here: leap to where the ray leaves the empty square around this cell, if its z
      // range stays within these bands until then.
      int radius = 255;
      for (std::size_t b = from; b < to; ++b) radius = std::min<int>(radius, empty_radius_[b]);
      const int k = radius - 1;  // the cells within k of this one are empty in these bands
      double t_leap = t1;
      int leap_axis = -1;
      for (int a = 0; a < 2 && k > 0; ++a) {
        if (step[a] == 0) continue;
        const int edge = cell[a] + (step[a] > 0 ? k + 1 : -k);
        const double t = (min_[a] + edge * cell_m_ - origin[a]) * inverse[a];
        if (t < t_leap) {
          t_leap = t;
          leap_axis = a;
        }
      }
      const double z_leap = origin.z() + t_leap * direction.z();
      if (k > 0 && t_leap > exit && BandOf(z_leap - kSlackM) >= band_lo &&
          BandOf(z_leap + kSlackM) <= band_hi) {
        if (leap_axis < 0) break;  // empty up to t1
        // On into the cell beyond the square; across the other axis, the cell at t_leap (kept
        // within the square: at a corner, rounding cannot skip a cell the ray crosses).
        const int other = 1 - leap_axis;
        cell[leap_axis] += step[leap_axis] * (k + 1);
        const double across =
            std::floor((origin[other] + t_leap * direction[other] - min_[other]) / cell_m_);
        cell[other] = static_cast<int>(
            std::clamp(across, std::max(0.0, cell[other] - static_cast<double>(k)),
                       std::min(count[other] - 1.0, cell[other] + static_cast<double>(k))));
        if (cell[leap_axis] < 0 || cell[leap_axis] >= count[leap_axis]) break;
        next[0] = boundary(0);
        next[1] = boundary(1);
        enter = t_leap;
        continue;
      }
    }
    for (std::uint32_t e = cell_start_[from]; e < cell_start_[to]; ++e) {
      const std::uint32_t i = cell_triangles_[e];
      const Triangle& tri = triangles_[i];
      if (tri.box_min.z() > z_hi || tri.box_max.z() < z_lo) continue;
      const double cos_normal = tri.unit_normal.dot(direction);
      if (std::abs(cos_normal) >= kPlaneCullMinCos) {
        // Where the ray meets the plane: within this cell's stretch, nearer than the best hit, and
        // within the triangle's box (coplanar neighbours, a wall's other panels, fail here).
        const double t_plane = (tri.unit_plane - tri.unit_normal.dot(origin)) / cos_normal;
        if (t_plane < lo || t_plane > hi || t_plane > best.t + kSlackM) continue;
        const Eigen::Vector3d at = origin + t_plane * direction;
        if ((at.array() < tri.box_min.array()).any() || (at.array() > tri.box_max.array()).any()) {
          continue;
        }
      }
      Test(i, origin, direction, max_t, &best);
    }
    // A hit within this cell's stretch: whatever lies in later cells is farther (to rounding).
    if (best.t <= exit || exit >= t1) break;
    const int a = next[0] <= next[1] ? 0 : 1;
    cell[a] += step[a];
    if (cell[a] < 0 || cell[a] >= count[a]) break;
    next[a] = boundary(a);
    enter = exit;
  }
  return best;
}

}  // namespace corridorsim::sim
