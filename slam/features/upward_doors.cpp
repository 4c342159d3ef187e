#include "slam/features/upward_doors.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <tuple>

#include <Eigen/LU>
#include <opencv2/imgproc.hpp>

namespace corridorsim::slam {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// The angle of `angle` counter-clockwise from `from`, in [0, 2 pi).
double CcwFrom(double from, double angle) {
  double d = std::remainder(angle - from, 2.0 * kPi);
  if (d < 0.0) d += 2.0 * kPi;
  return d;
}

double AngleOf(const Eigen::Vector2d& v) { return std::atan2(v.y(), v.x()); }

// Groups vertical lines into columns (P3 Fig. 5a): sorted by angle, neighbours closer than the
// gap join; the sequence starts after its widest gap so that a column across +-pi stays whole.
std::vector<DoorColumn> GroupColumns(const std::vector<UpwardLine>& lines,
                                     const Eigen::Vector2d& pp, const UpwardDoorOptions& o) {
  std::vector<const UpwardLine*> vertical;
  for (const UpwardLine& l : lines) {
    if (l.vertical) vertical.push_back(&l);
  }
  std::vector<DoorColumn> columns;
  if (vertical.empty()) return columns;
  std::sort(vertical.begin(), vertical.end(), [](const UpwardLine* x, const UpwardLine* y) {
    return x->angle_rad < y->angle_rad ||
           (x->angle_rad == y->angle_rad && x->a_px.x() < y->a_px.x());
  });
  const std::size_t n = vertical.size();
  std::size_t start = 0;
  double widest = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double gap = CcwFrom(vertical[(i + n - 1) % n]->angle_rad, vertical[i]->angle_rad);
    if (gap > widest) {
      widest = gap;
      start = i;
    }
  }
  const double gap_rad = o.group_gap_deg * kDeg;
  std::vector<const UpwardLine*> group;
  const auto close_group = [&]() {
    if (group.empty()) return;
    // The column is the longest line and the lines of the group that continue it radially
    // (overlapping or within max_column_gap_px of it): a ceiling line that happens to point at
    // the centre at the same angle does not move the column's top.
    const auto radii = [&](const UpwardLine* l) {
      const double ra = (l->a_px - pp).norm(), rb = (l->b_px - pp).norm();
      return std::pair<double, double>(std::min(ra, rb), std::max(ra, rb));
    };
    std::stable_sort(group.begin(), group.end(), [](const UpwardLine* x, const UpwardLine* y) {
      return (x->b_px - x->a_px).squaredNorm() > (y->b_px - y->a_px).squaredNorm();
    });
    DoorColumn c;
    std::tie(c.top_radius_px, c.bottom_radius_px) = radii(group.front());
    std::vector<bool> used(group.size(), false);
    used[0] = true;
    for (bool grew = true; grew;) {
      grew = false;
      for (std::size_t g = 1; g < group.size(); ++g) {
        if (used[g]) continue;
        const auto [lo, hi] = radii(group[g]);
        if (lo > c.bottom_radius_px + o.max_column_gap_px ||
            hi < c.top_radius_px - o.max_column_gap_px) {
          continue;
        }
        used[g] = grew = true;
        c.top_radius_px = std::min(c.top_radius_px, lo);
        c.bottom_radius_px = std::max(c.bottom_radius_px, hi);
      }
    }
    Eigen::Vector2d direction = Eigen::Vector2d::Zero();
    for (std::size_t g = 0; g < group.size(); ++g) {
      if (!used[g]) continue;
      const double length = (group[g]->b_px - group[g]->a_px).norm();
      direction +=
          length * Eigen::Vector2d(std::cos(group[g]->angle_rad), std::sin(group[g]->angle_rad));
      ++c.lines;
    }
    c.angle_rad = AngleOf(direction);
    // The top on the column's mean ray (the lines of a column are a few pixels apart).
    c.top_px = pp + c.top_radius_px * Eigen::Vector2d(std::cos(c.angle_rad), std::sin(c.angle_rad));
    if (c.bottom_radius_px - c.top_radius_px >= o.min_column_px) columns.push_back(c);
    group.clear();
  };
  for (std::size_t k = 0; k < n; ++k) {
    const UpwardLine* l = vertical[(start + k) % n];
    if (!group.empty() && CcwFrom(group.back()->angle_rad, l->angle_rad) > gap_rad) close_group();
    group.push_back(l);
  }
  close_group();
  // Longest first, then by angle (a total order: the result does not depend on the sort).
  std::sort(columns.begin(), columns.end(), [](const DoorColumn& x, const DoorColumn& y) {
    const double lx = x.bottom_radius_px - x.top_radius_px;
    const double ly = y.bottom_radius_px - y.top_radius_px;
    return lx > ly || (lx == ly && x.angle_rad < y.angle_rad);
  });
  if (columns.size() > std::size_t(o.max_columns)) columns.resize(std::size_t(o.max_columns));
  return columns;
}

// The distance from the principal point to the chord p1 p2 along the direction at `angle`
// (infinity when the direction misses the chord).
double ChordRadius(const Eigen::Vector2d& p1, const Eigen::Vector2d& p2, double angle) {
  const Eigen::Vector2d d(std::cos(angle), std::sin(angle));
  const Eigen::Vector2d e = p2 - p1;
  // p1 + s e = r d  =>  [d, -e] [r; s] = p1
  Eigen::Matrix2d m;
  m << d, -e;
  const double det = m.determinant();
  if (std::abs(det) < 1e-9) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d rs = m.inverse() * p1;
  return rs(0) > 0.0 ? rs(0) : std::numeric_limits<double>::infinity();
}

}  // namespace

std::optional<OptionsProblem> UpwardDoorOptions::Check() const {
  if (auto p = CheckOptionBounds(UpwardDoorOptionsTable(), *this)) return p;
  if (max_door_angle_deg < min_door_angle_deg) {
    return OptionsProblem{"max_door_angle_deg", "must be at least min_door_angle_deg"};
  }
  return std::nullopt;
}

bool BarSlopeAllowed(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                     const Eigen::Vector2d& top_a, const Eigen::Vector2d& top_b,
                     const Eigen::Vector2d& principal_point) {
  const double theta1 = AngleOf(top_a - principal_point);
  const double theta2 = AngleOf(top_b - principal_point);
  const double limit = CcwFrom(theta2, theta1 + kPi);  // theta1 + 180 - theta2
  // A segment has no sense: either direction may be the bar's.
  for (const double psi : {AngleOf(to - from), AngleOf(from - to)}) {
    if (CcwFrom(theta2, psi) <= limit) return true;
  }
  return false;
}

UpwardDoorDetection DetectUpwardDoorCandidates(const cv::Mat& grey,
                                               const Eigen::Vector2d& principal_point,
                                               const UpwardDoorOptions& o) {
  CheckOrDie(grey.type() == CV_8UC1, "slam::DetectUpwardDoorCandidates", "needs a grey image");
  UpwardDoorDetection out;
  if (grey.empty()) return out;
  const Eigen::Vector2d& pp = principal_point;

  std::vector<cv::Vec4f> segments;
  cv::Ptr<cv::LineSegmentDetector> lsd =
      cv::createLineSegmentDetector(cv::LSD_REFINE_STD, o.lsd_scale);
  lsd->detect(grey, segments);
  std::vector<UpwardLine> lines;
  const double cos_tolerance = std::cos(o.radial_tolerance_deg * kDeg);
  for (const cv::Vec4f& s : segments) {
    UpwardLine l;
    l.a_px = Eigen::Vector2d(s[0], s[1]);
    l.b_px = Eigen::Vector2d(s[2], s[3]);
    const Eigen::Vector2d d = l.b_px - l.a_px;
    const double length = d.norm();
    if (!(length >= o.min_line_px)) continue;
    const Eigen::Vector2d radial = 0.5 * (l.a_px + l.b_px) - pp;
    if (radial.norm() < o.min_radius_px) continue;
    l.angle_rad = AngleOf(radial);
    l.vertical = std::abs(d.dot(radial)) >= cos_tolerance * length * radial.norm();
    lines.push_back(l);
  }
  std::stable_sort(lines.begin(), lines.end(), [](const UpwardLine& x, const UpwardLine& y) {
    return (x.b_px - x.a_px).squaredNorm() > (y.b_px - y.a_px).squaredNorm();
  });
  if (lines.size() > std::size_t(o.max_lines)) lines.resize(std::size_t(o.max_lines));
  out.columns = GroupColumns(lines, pp, o);

  // P3 Fig. 5b: every pair of columns; eqs. 3-4: a bar in its search area.
  const double min_span = o.min_door_angle_deg * kDeg, max_span = o.max_door_angle_deg * kDeg;
  for (std::size_t i = 0; i < out.columns.size(); ++i) {
    for (std::size_t j = i + 1; j < out.columns.size(); ++j) {
      int ia = int(i), ib = int(j);
      double span = CcwFrom(out.columns[i].angle_rad, out.columns[j].angle_rad);
      if (span > kPi) {
        std::swap(ia, ib);
        span = 2.0 * kPi - span;
      }
      if (span < min_span || span > max_span) continue;
      const DoorColumn& ca = out.columns[std::size_t(ia)];
      const DoorColumn& cb = out.columns[std::size_t(ib)];
      const double ratio = std::max(ca.top_radius_px, cb.top_radius_px) /
                           std::max(std::min(ca.top_radius_px, cb.top_radius_px), 1e-9);
      if (ratio > o.max_top_ratio) continue;
      const Eigen::Vector2d p1 = ca.top_px - pp, p2 = cb.top_px - pp;
      // Angular intervals (from column a, in [0, span]) the qualifying bar lines cover.
      std::vector<std::pair<double, double>> covered;
      const double slack = o.bar_angle_slack * span;
      for (const UpwardLine& l : lines) {
        if (l.vertical) continue;
        double da = CcwFrom(ca.angle_rad, AngleOf(l.a_px - pp));
        double db = CcwFrom(ca.angle_rad, AngleOf(l.b_px - pp));
        if (da > kPi + span / 2) da -= 2.0 * kPi;
        if (db > kPi + span / 2) db -= 2.0 * kPi;
        const auto inside = [&](double offset, const Eigen::Vector2d& p) {
          if (offset < -slack || offset > span + slack) return false;
          const double chord = ChordRadius(p1, p2, ca.angle_rad + offset);
          const double r = (p - pp).norm();
          return r <= (1.0 + o.bar_margin) * chord && r >= (1.0 - o.bar_margin) * chord;
        };
        if (!inside(da, l.a_px) || !inside(db, l.b_px)) continue;
        if (!BarSlopeAllowed(l.a_px, l.b_px, ca.top_px, cb.top_px, pp)) continue;
        covered.emplace_back(std::clamp(std::min(da, db), 0.0, span),
                             std::clamp(std::max(da, db), 0.0, span));
      }
      std::sort(covered.begin(), covered.end());
      double total = 0.0, reach = 0.0;
      for (const auto& [lo, hi] : covered) {
        const double from = std::max(lo, reach);
        if (hi > from) total += hi - from;
        reach = std::max(reach, hi);
      }
      const double coverage = span > 0.0 ? total / span : 0.0;
      if (coverage < o.min_bar_coverage) continue;
      UpwardDoorCandidate c;
      c.column_a = ia;
      c.column_b = ib;
      c.angle_a_rad = ca.angle_rad;
      c.angle_b_rad = cb.angle_rad;
      c.top_a_px = ca.top_px;
      c.top_b_px = cb.top_px;
      c.bar_coverage = coverage;
      out.candidates.push_back(c);
    }
  }
  std::sort(out.candidates.begin(), out.candidates.end(),
            [](const UpwardDoorCandidate& x, const UpwardDoorCandidate& y) {
              if (x.bar_coverage != y.bar_coverage) return x.bar_coverage > y.bar_coverage;
              if (x.column_a != y.column_a) return x.column_a < y.column_a;
              return x.column_b < y.column_b;
            });
  if (out.candidates.size() > std::size_t(o.max_candidates)) {
    out.candidates.resize(std::size_t(o.max_candidates));
  }
  out.lines = std::move(lines);
  return out;
}

}  // namespace corridorsim::slam
