#pragma once
// P3 section III-A (P2 sections 3-4): door candidates in an upward camera's image. A door is
// two vertical columns and a horizontal bar (P3 Fig. 4).
// - Line segments by LSD (the Line Segment Detector of OpenCV's imgproc).
// - Vertical lines: a line perpendicular to the floor lies, with the vertical optical axis of an
//   upward camera, in a plane through that axis, so its image points at the principal point
//   whatever the lens (radially symmetric: pinhole or Kannala-Brandt). A segment is vertical when
//   its direction is within `radial_tolerance_deg` of the ray from the principal point through
//   its midpoint.
// - Neighbouring vertical lines (angles about the principal point within `group_gap_deg`) are
//   grouped into one column (P3 Fig. 5a); a column's top is its point nearest the principal
//   point (the higher a point, the nearer the image centre).
// - Each of the n(n-1)/2 pairs of columns whose angular separation is a door's (P3 Fig. 5b) is a
//   candidate when a horizontal line lies in its search area (P3 Fig. 6, eqs. 3-4): the bar's
//   end points are t1 p1 and t2 p2 (p1, p2 the column tops from the principal point), so its
//   direction lies between the angle of p2 and that of p1 + 180 degrees (eq. 4). Here a bar
//   segment must have that slope, its ends within `bar_angle_slack` of the columns' angle
//   outside them and within `bar_margin` of the chord p1 p2 radially; the segments that qualify
//   must cover `min_bar_coverage` of the angle between the columns.
// A pure function of the image and the options.

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/error.h"
#include "common/options_table.h"

namespace corridorsim::slam {

struct UpwardDoorOptions {
  double lsd_scale = 0.5;             // LSD's image scale (1 = full resolution; 0.5 is 3x faster)
  double min_line_px = 12.0;          // shorter segments are ignored
  double radial_tolerance_deg = 3.0;  // a vertical line points at the principal point within this
  double min_radius_px = 30.0;        // segments whose midpoint is nearer the centre are ignored
  double group_gap_deg = 5.0;         // vertical lines this close in angle form one column
  double max_column_gap_px = 4.0;     // radial gap between the lines of one column at most
  double min_column_px = 25.0;        // a column's radial extent at least this
  double min_door_angle_deg = 12.0;   // angular separation of a door's columns about the centre
  double max_door_angle_deg = 80.0;
  double max_top_ratio = 1.6;     // larger over smaller column-top radius at most
  double bar_margin = 0.1;        // bar lines lie within this fraction of the tops' chord radially
  double bar_angle_slack = 0.15;  // the bar may reach this fraction of the span past a column
  double min_bar_coverage = 0.6;  // of the columns' angular separation covered by bar lines
  int max_lines = 2000;           // LSD segments considered at most (bounds the time)
  int max_columns = 24;           // columns kept, longest first
  int max_candidates = 32;
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<UpwardDoorOptions>& UpwardDoorOptionsTable();

/// A line segment with its polar description about the principal point.
struct UpwardLine {
  Eigen::Vector2d a_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d b_px = Eigen::Vector2d::Zero();
  double angle_rad = 0.0;  // of its midpoint about the principal point, atan2(v - cy, u - cx)
  bool vertical = false;   // points at the principal point
};

/// A group of neighbouring vertical lines: one door column (P3 Fig. 5a).
struct DoorColumn {
  double angle_rad = 0.0;  // length-weighted mean angle about the principal point
  Eigen::Vector2d top_px = Eigen::Vector2d::Zero();  // its point nearest the principal point
  double top_radius_px = 0.0;
  double bottom_radius_px = 0.0;  // its point farthest from the principal point
  int lines = 0;
};

/// A pair of columns with a bar in its search area (P3 Fig. 5b, 6d). Column a is the first in
/// counter-clockwise image angle (b lies less than 180 degrees counter-clockwise of a).
struct UpwardDoorCandidate {
  int column_a = 0;  // indices into UpwardDoorDetection::columns
  int column_b = 0;
  double angle_a_rad = 0.0;
  double angle_b_rad = 0.0;
  Eigen::Vector2d top_a_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d top_b_px = Eigen::Vector2d::Zero();
  double bar_coverage = 0.0;  // fraction of the angular separation the bar lines cover
};

struct UpwardDoorDetection {
  std::vector<UpwardLine> lines;  // every segment kept (vertical or not)
  std::vector<DoorColumn> columns;
  std::vector<UpwardDoorCandidate> candidates;  // best bar coverage first
};

/// P3 section III-A on a grey image; `principal_point` in pixels.
UpwardDoorDetection DetectUpwardDoorCandidates(const cv::Mat& grey,
                                               const Eigen::Vector2d& principal_point,
                                               const UpwardDoorOptions& options);

/// P3 eq. 4: whether a segment from `from` to `to` (pixels, about `principal_point`) has the
/// slope of a bar between the column tops p1 (a) and p2 (b): its direction lies between the
/// angle of p2 and that of p1 + 180 degrees, taken either way along the segment.
bool BarSlopeAllowed(const Eigen::Vector2d& from, const Eigen::Vector2d& to,
                     const Eigen::Vector2d& top_a, const Eigen::Vector2d& top_b,
                     const Eigen::Vector2d& principal_point);

}  // namespace corridorsim::slam
