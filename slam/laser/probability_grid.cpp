#include "slam/laser/probability_grid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace corridorsim::slam::laser {
namespace {

constexpr int kTileCells = 128;  // the grid grows by whole tiles of cells (6.4 m at 5 cm)

double Odds(double p) { return p / (1.0 - p); }
double ProbabilityFromOdds(double odds) { return odds / (1.0 + odds); }

}  // namespace

ProbabilityGrid::ProbabilityGrid(const ProbabilityGridOptions& options)
    : options_(options),
      hit_odds_(Odds(options.hit_probability)),
      miss_odds_(Odds(options.miss_probability)) {}

void ProbabilityGrid::Cover(const Eigen::Vector2d& lo_in, const Eigen::Vector2d& hi_in) {
  const double res = options_.resolution_m;
  const Eigen::Vector2d lo = lo_in.cwiseMax(limit_lo_);
  const Eigen::Vector2d hi = hi_in.cwiseMin(limit_hi_);
  if (!(lo.array() <= hi.array()).all()) return;
  const double tile = kTileCells * res;
  if (rows_ > 0) {
    const Eigen::Vector2d top = origin_ + Eigen::Vector2d(cols_, rows_) * res;
    if ((lo.array() >= origin_.array()).all() && (hi.array() < top.array()).all()) return;
  }
  // The new bounds: the old ones and [lo, hi], on tile boundaries measured from the extent's
  // lower corner (so the cells never shift against the world).
  Eigen::Vector2d new_lo = lo, new_hi = hi;
  if (rows_ > 0) {
    new_lo = new_lo.cwiseMin(origin_);
    new_hi = new_hi.cwiseMax(origin_ + Eigen::Vector2d(cols_, rows_) * res);
  }
  Eigen::Vector2d snapped_lo, snapped_hi;
  for (int a = 0; a < 2; ++a) {
    snapped_lo[a] = limit_lo_[a] + std::floor((new_lo[a] - limit_lo_[a]) / tile) * tile;
    snapped_hi[a] = limit_lo_[a] + (std::floor((new_hi[a] - limit_lo_[a]) / tile) + 1) * tile;
  }
  const int new_cols = static_cast<int>(std::lround((snapped_hi.x() - snapped_lo.x()) / res));
  const int new_rows = static_cast<int>(std::lround((snapped_hi.y() - snapped_lo.y()) / res));
  const int shift_col = static_cast<int>(std::lround((origin_.x() - snapped_lo.x()) / res));
  const int shift_row = static_cast<int>(std::lround((origin_.y() - snapped_lo.y()) / res));
  std::vector<float> probability(static_cast<std::size_t>(new_rows) * new_cols, 0.0f);
  std::vector<std::uint32_t> updated(probability.size(), 0);
  for (int r = 0; r < rows_; ++r) {
    const std::size_t from = static_cast<std::size_t>(r) * cols_;
    const std::size_t to = static_cast<std::size_t>(r + shift_row) * new_cols + shift_col;
    std::copy_n(probability_.begin() + from, cols_, probability.begin() + to);
    std::copy_n(updated_.begin() + from, cols_, updated.begin() + to);
  }
  probability_ = std::move(probability);
  updated_ = std::move(updated);
  origin_ = snapped_lo;
  rows_ = new_rows;
  cols_ = new_cols;
}

void ProbabilityGrid::Update(int row, int col, double odds_factor) {
  const std::size_t i = static_cast<std::size_t>(row) * cols_ + col;
  if (updated_[i] == scan_count_) return;  // once per scan (Cartographer's update markers)
  updated_[i] = scan_count_;
  const double p = probability_[i] == 0.0f ? 0.5 : probability_[i];
  const double updated = ProbabilityFromOdds(Odds(p) * odds_factor);
  probability_[i] = static_cast<float>(std::clamp(updated, kMinProbability, kMaxProbability));
}

void ProbabilityGrid::InsertScan(const Eigen::Vector2d& origin,
                                 const std::vector<Eigen::Vector2d>& endpoints) {
  if (rows_ == 0 && cols_ == 0 && scan_count_ == 0) {
    // The bounded extent, centred on the first scan's origin.
    limit_lo_ = origin - Eigen::Vector2d::Constant(options_.max_extent_m);
    limit_hi_ = origin + Eigen::Vector2d::Constant(options_.max_extent_m);
  }
  const auto inside = [&](const Eigen::Vector2d& p) {
    return (p.array() >= limit_lo_.array()).all() && (p.array() < limit_hi_.array()).all();
  };
  if (!inside(origin)) return;
  Eigen::Vector2d lo = origin, hi = origin;
  std::vector<Eigen::Vector2d> kept;
  kept.reserve(endpoints.size());
  for (const Eigen::Vector2d& p : endpoints) {
    if (!p.allFinite() || !inside(p)) continue;
    kept.push_back(p);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  Cover(lo, hi);
  // Marker 0 means "never updated": scans count from 1 (2^32 scans would take years).
  ++scan_count_;
  const auto cell_of = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d g = GridCoordinates(p);
    return Eigen::Vector2i(static_cast<int>(std::lround(g.x())),
                           static_cast<int>(std::lround(g.y())));
  };
  // Hits first, so that a cell that is both some beam's endpoint and another's crossing counts
  // as a hit (Cartographer inserts hits before misses too).
  std::vector<Eigen::Vector2i> hit_cells;
  hit_cells.reserve(kept.size());
  for (const Eigen::Vector2d& p : kept) {
    const Eigen::Vector2i c = cell_of(p);
    hit_cells.push_back(c);
    if (Contains(c.y(), c.x())) Update(c.y(), c.x(), hit_odds_);
  }
  const Eigen::Vector2i start = cell_of(origin);
  for (const Eigen::Vector2i& end : hit_cells) {
    // Bresenham's line from the origin's cell to the endpoint's, the endpoint excluded.
    int x = start.x(), y = start.y();
    const int dx = std::abs(end.x() - x), dy = -std::abs(end.y() - y);
    const int sx = x < end.x() ? 1 : -1, sy = y < end.y() ? 1 : -1;
    int err = dx + dy;
    while (x != end.x() || y != end.y()) {
      if (Contains(y, x)) Update(y, x, miss_odds_);
      const int e2 = 2 * err;
      if (e2 >= dy) {
        err += dy;
        x += sx;
      }
      if (e2 <= dx) {
        err += dx;
        y += sy;
      }
    }
  }
}

Eigen::Vector2d ProbabilityGrid::GridCoordinates(const Eigen::Vector2d& point) const {
  return (point - origin_) / options_.resolution_m - Eigen::Vector2d::Constant(0.5);
}

double ProbabilityGrid::CorrespondenceCost(int row, int col) const {
  if (!Contains(row, col)) return kMaxCorrespondenceCost;
  const float p = probability_[static_cast<std::size_t>(row) * cols_ + col];
  return p == 0.0f ? kMaxCorrespondenceCost : 1.0 - p;
}

double ProbabilityGrid::ProbabilityAt(const Eigen::Vector2d& point) const {
  const Eigen::Vector2d g = GridCoordinates(point);
  const double col = std::round(g.x()), row = std::round(g.y());
  if (!(row >= 0 && col >= 0 && row < rows_ && col < cols_)) return 0.0;
  return probability_[static_cast<std::size_t>(row) * cols_ + static_cast<std::size_t>(col)];
}

std::int64_t ProbabilityGrid::known_cells() const {
  return std::count_if(probability_.begin(), probability_.end(), [](float p) { return p != 0.0f; });
}

std::string ProbabilityGrid::ToPgm() const {
  char header[160];
  std::snprintf(header, sizeof header, "P5\n# resolution_m %.6f origin_m %.6f %.6f\n%d %d\n255\n",
                options_.resolution_m, origin_.x(), origin_.y(), cols_, rows_);
  std::string bytes = header;
  const std::size_t start = bytes.size();
  bytes.resize(start + static_cast<std::size_t>(rows_) * cols_);
  for (int r = 0; r < rows_; ++r) {
    const int source_row = rows_ - 1 - r;  // PGM rows run from the top
    for (int c = 0; c < cols_; ++c) {
      const float p = probability_[static_cast<std::size_t>(source_row) * cols_ + c];
      const int value = p == 0.0f ? 205 : static_cast<int>(std::lround(254.0 * (1.0 - p)));
      bytes[start + static_cast<std::size_t>(r) * cols_ + c] = static_cast<char>(value);
    }
  }
  return bytes;
}

}  // namespace corridorsim::slam::laser
