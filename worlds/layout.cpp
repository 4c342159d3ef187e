#include "worlds/layout.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace corridorsim::worlds {
namespace {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;

std::string Metres(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.2f m", v);
  return buf;
}

// Centre lines of the corridors of each layout (frame W: first corridor along +x from the origin).
std::vector<std::pair<Vector2d, Vector2d>> CentreLines(const WorldOptions& s) {
  const double l = s.length_m, l2 = s.second_length_m;
  switch (s.layout) {
    case Layout::kStraight:
      return {{{0, 0}, {l, 0}}};
    case Layout::kLTurn:
      return {{{0, 0}, {l, 0}}, {{l, 0}, {l, l2}}};
    case Layout::kTJunction:
      return {{{0, 0}, {l, 0}}, {{l / 2, 0}, {l / 2, l2}}};
    case Layout::kLoop:
      return {{{0, 0}, {l, 0}}, {{l, 0}, {l, l2}}, {{l, l2}, {0, l2}}, {{0, l2}, {0, 0}}};
  }
  return {};
}

// Walkable rectangle of a centre line. Segments that start or end at a corner are extended by
// half a width there so that corners are covered; the first corridor's start is the origin.
AlignedBox2d SegmentRect(const WorldOptions& s, const Vector2d& a, const Vector2d& b,
                         bool extend_start, bool extend_end) {
  const Vector2d dir = (b - a).normalized();
  const Vector2d side(-dir.y(), dir.x());
  const double h = s.width_m / 2;
  const Vector2d a2 = a - (extend_start ? h : 0.0) * dir;
  const Vector2d b2 = b + (extend_end ? h : 0.0) * dir;
  AlignedBox2d box(a2 + h * side);
  box.extend(a2 - h * side);
  box.extend(b2 + h * side);
  box.extend(b2 - h * side);
  return box;
}

std::vector<double> Unique(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  std::vector<double> out;
  for (const double x : v) {
    if (out.empty() || x - out.back() > 1e-9) out.push_back(x);
  }
  return out;
}

// Boundary of the union of axis-aligned rectangles, by coordinate compression: a cell of the
// grid of all rectangle edges is inside or outside, and walls run where the two sides differ.
std::vector<Wall> UnionBoundary(const std::vector<AlignedBox2d>& rects,
                                std::vector<AlignedBox2d>* cells) {
  std::vector<double> xs_raw, ys_raw;
  for (const auto& r : rects) {
    xs_raw.insert(xs_raw.end(), {r.min().x(), r.max().x()});
    ys_raw.insert(ys_raw.end(), {r.min().y(), r.max().y()});
  }
  const std::vector<double> xs = Unique(xs_raw), ys = Unique(ys_raw);
  const int nx = static_cast<int>(xs.size()) - 1, ny = static_cast<int>(ys.size()) - 1;
  auto inside = [&](int i, int j) {
    if (i < 0 || j < 0 || i >= nx || j >= ny) return false;
    const Vector2d c((xs[i] + xs[i + 1]) / 2, (ys[j] + ys[j + 1]) / 2);
    return std::any_of(rects.begin(), rects.end(),
                       [&](const AlignedBox2d& r) { return r.contains(c); });
  };
  cells->clear();
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      if (inside(i, j)) cells->emplace_back(Vector2d(xs[i], ys[j]), Vector2d(xs[i + 1], ys[j + 1]));
    }
  }
  std::vector<Wall> walls;
  auto add = [&](Vector2d a, Vector2d b, Vector2d n) {
    const Vector2d t = (b - a).normalized();
    if (Vector2d(-t.y(), t.x()).dot(n) < 0) std::swap(a, b);  // inward normal on the left
    Wall w;
    w.start = a;
    w.end = b;
    w.inward_normal = n;
    walls.push_back(w);
  };
  // Vertical walls (x = xs[i]), merged along y.
  for (int i = 0; i <= nx; ++i) {
    int run_start = -1, run_sign = 0;
    for (int j = 0; j <= ny; ++j) {
      int sign = 0;
      if (j < ny) sign = inside(i, j) == inside(i - 1, j) ? 0 : (inside(i, j) ? 1 : -1);
      if (sign != run_sign) {
        if (run_sign != 0) add({xs[i], ys[run_start]}, {xs[i], ys[j]}, {double(run_sign), 0});
        run_start = j;
        run_sign = sign;
      }
    }
  }
  // Horizontal walls (y = ys[j]), merged along x.
  for (int j = 0; j <= ny; ++j) {
    int run_start = -1, run_sign = 0;
    for (int i = 0; i <= nx; ++i) {
      int sign = 0;
      if (i < nx) sign = inside(i, j) == inside(i, j - 1) ? 0 : (inside(i, j) ? 1 : -1);
      if (sign != run_sign) {
        if (run_sign != 0) add({xs[run_start], ys[j]}, {xs[i], ys[j]}, {0, double(run_sign)});
        run_start = i;
        run_sign = sign;
      }
    }
  }
  return walls;
}

}  // namespace

double UsableWallLength(const Wall& wall, const WorldOptions& options) {
  return std::max(0.0, wall.length() - 2 * options.doors.min_gap_m);
}

std::optional<OptionsProblem> PlanLayout(const WorldOptions& options, int first_id,
                                         LayoutPlan* plan) {
  *plan = LayoutPlan();
  int next_id = first_id;
  const auto lines = CentreLines(options);
  for (std::size_t k = 0; k < lines.size(); ++k) {
    CorridorSegment seg;
    seg.id = next_id++;
    seg.start = lines[k].first;
    seg.end = lines[k].second;
    seg.width_m = options.width_m;
    seg.height_m = options.height_m;
    plan->segments.push_back(seg);
    const bool corner_start = k > 0 && options.layout != Layout::kTJunction;
    const bool corner_end =
        options.layout == Layout::kLoop || (options.layout == Layout::kLTurn && k == 0);
    plan->segment_rects.push_back(
        SegmentRect(options, seg.start, seg.end, corner_start, corner_end));
  }
  // The T's branch starts on the main corridor's centre line: extend it across the main corridor.
  if (options.layout == Layout::kTJunction)
    plan->segment_rects[1].extend(Vector2d(options.length_m / 2, 0));

  plan->walls = UnionBoundary(plan->segment_rects, &plan->floor_cells);
  for (Wall& w : plan->walls) {
    w.id = next_id++;
    const Vector2d probe = (w.start + w.end) / 2 + 1e-3 * w.inward_normal;
    // Prefer the segment the wall runs along; corner squares belong to two segments.
    int best = -1;
    for (std::size_t k = 0; k < plan->segments.size(); ++k) {
      if (!plan->segment_rects[k].contains(probe)) continue;
      const bool parallel = std::abs(plan->segments[k].direction().dot(w.tangent())) > 0.99;
      if (best < 0 || parallel) best = static_cast<int>(k);
      if (parallel) break;
    }
    if (best < 0) best = 0;
    w.segment_id = plan->segments[best].id;
    w.side_wall = std::abs(plan->segments[best].direction().dot(w.tangent())) > 0.99;
  }

  // Doorways per side wall: D'Hondt allocation by usable length, bounded by each wall's capacity.
  const double f = options.doors.width_m + 2 * options.doors.frame_width_m;
  plan->door_footprint_m = f;
  const double g = options.doors.min_gap_m;
  plan->doors_per_wall.assign(plan->walls.size(), 0);
  std::vector<int> capacity(plan->walls.size(), 0);
  double longest_usable = 0.0;
  int total_capacity = 0;
  for (std::size_t k = 0; k < plan->walls.size(); ++k) {
    if (!plan->walls[k].side_wall) continue;
    const double usable = UsableWallLength(plan->walls[k], options);
    longest_usable = std::max(longest_usable, usable);
    capacity[k] =
        usable + 1e-9 >= f ? static_cast<int>(std::floor((usable - f) / (f + g) + 1e-9)) + 1 : 0;
    total_capacity += capacity[k];
  }
  if (options.doors.count > 0 && longest_usable + 1e-9 < f) {
    return OptionsProblem{
        "doors.width_m", "a doorway of " + Metres(f) + " with its frame is wider than every wall " +
                             "segment (longest usable wall: " + Metres(longest_usable) + ")"};
  }
  if (options.doors.count > total_capacity) {
    return OptionsProblem{"doors.count", std::to_string(options.doors.count) +
                                             " doorways do not fit on the side walls: at most " +
                                             std::to_string(total_capacity) + " fit with width_m " +
                                             Metres(options.doors.width_m) + " and min_gap_m " +
                                             Metres(g)};
  }
  for (int placed = 0; placed < options.doors.count; ++placed) {
    int best = -1;
    double best_quotient = -1.0;
    for (std::size_t k = 0; k < plan->walls.size(); ++k) {
      if (plan->doors_per_wall[k] >= capacity[k]) continue;
      const double q = UsableWallLength(plan->walls[k], options) / (plan->doors_per_wall[k] + 1);
      if (q > best_quotient + 1e-12) {
        best_quotient = q;
        best = static_cast<int>(k);
      }
    }
    ++plan->doors_per_wall[best];
  }
  return std::nullopt;
}

}  // namespace corridorsim::worlds
