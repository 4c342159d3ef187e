#include "worlds/map_plot.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace corridorsim::worlds {
namespace {

using Eigen::Vector2d;

// Scale and canvas.
constexpr double kTargetLongestSidePx = 2400.0;
constexpr double kMinAutoPxPerM = 20.0;
constexpr double kMaxAutoPxPerM = 80.0;
constexpr int kMaxSidePx = 20000;
constexpr int kMarginPx = 70;           // around the plan: room for labels outside the walls
constexpr int kMinCanvasWidthPx = 720;  // so the title and legend have room on small plans
constexpr int kPadPx = 12;
constexpr double kDefaultWallThicknessM = 0.15;

// Shapes are drawn with sub-pixel precision: points are fixed-point with kShift fraction bits.
constexpr int kShift = 4;
constexpr double kSubpixel = 1 << kShift;

// Text: FONT_HERSHEY_SIMPLEX digits are about 21 px tall per unit of scale.
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kLabelScale = 0.6;  // room numbers, ~13 px
constexpr double kTagScale = 0.45;   // distractor letters
constexpr double kTitleScale = 0.75;
constexpr double kTextScale = 0.5;  // counts line and legend
constexpr int kLegendRowPx = 30;

// The canvas holds RGB (not OpenCV's usual BGR), so its bytes copy straight into Image8.
cv::Scalar Rgb(int r, int g, int b) { return cv::Scalar(r, g, b); }
const cv::Scalar kWhite = Rgb(255, 255, 255);
const cv::Scalar kBlack = Rgb(0, 0, 0);
const cv::Scalar kText = Rgb(20, 20, 20);
const cv::Scalar kFloor = Rgb(214, 214, 214);
const cv::Scalar kRoomFloor = Rgb(238, 234, 222);
const cv::Scalar kWallColor = Rgb(55, 55, 60);
const cv::Scalar kColumn = Rgb(20, 20, 20);
const cv::Scalar kClosed = Rgb(215, 40, 40);
const cv::Scalar kOpen = Rgb(30, 160, 60);
const cv::Scalar kEmpty = Rgb(40, 90, 220);
const cv::Scalar kLampOn = Rgb(255, 215, 0);
const cv::Scalar kLampOnEdge = Rgb(170, 130, 0);
const cv::Scalar kLampOff = Rgb(165, 165, 165);
const cv::Scalar kLampOffEdge = Rgb(100, 100, 100);
const cv::Scalar kReflector = Rgb(0, 190, 230);
const cv::Scalar kDistractor = Rgb(150, 150, 150);
const cv::Scalar kDistractorEdge = Rgb(80, 80, 80);

cv::Point Fixed(const Vector2d& px) {
  return {cvRound(px.x() * kSubpixel), cvRound(px.y() * kSubpixel)};
}
cv::Point Rounded(const Vector2d& px) { return {cvRound(px.x()), cvRound(px.y())}; }

Vector2d Perpendicular(const Vector2d& d) { return {-d.y(), d.x()}; }  // d turned left

double WallThicknessM(const World& world) {
  return world.options.wall_thickness_m > 0.0 ? world.options.wall_thickness_m
                                              : kDefaultWallThicknessM;
}

// ---------------------------------------------------------------------------------------------
// Geometry of the plan (metres, frame W)

using Quad = std::array<Vector2d, 4>;

double DistanceToSegment(const Vector2d& p, const Vector2d& a, const Vector2d& b) {
  const Vector2d ab = b - a;
  const double length2 = ab.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((p - a).dot(ab) / length2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

// Walkable area of each segment: its rectangle, extended by width/2 at an end that lies inside
// another segment (a junction or a turn), so corners are filled.
std::vector<Quad> FloorQuads(const World& world) {
  const auto inside_other = [&](const Vector2d& p, std::size_t self) {
    for (std::size_t k = 0; k < world.segments.size(); ++k) {
      const CorridorSegment& other = world.segments[k];
      if (k != self && DistanceToSegment(p, other.start, other.end) <= 0.5 * other.width_m + 1e-6) {
        return true;
      }
    }
    return false;
  };
  std::vector<Quad> quads;
  for (std::size_t i = 0; i < world.segments.size(); ++i) {
    const CorridorSegment& segment = world.segments[i];
    if ((segment.end - segment.start).norm() <= 0.0) continue;
    const Vector2d d = segment.direction();
    const Vector2d half_width = Perpendicular(d) * 0.5 * segment.width_m;
    const double half = 0.5 * segment.width_m;
    const Vector2d a = segment.start - d * (inside_other(segment.start, i) ? half : 0.0);
    const Vector2d b = segment.end + d * (inside_other(segment.end, i) ? half : 0.0);
    quads.push_back({a - half_width, b - half_width, b + half_width, a + half_width});
  }
  return quads;
}

Quad Grown(const Eigen::AlignedBox2d& box, double by) {
  const Vector2d lo = box.min() - Vector2d::Constant(by);
  const Vector2d hi = box.max() + Vector2d::Constant(by);
  return {lo, Vector2d(hi.x(), lo.y()), hi, Vector2d(lo.x(), hi.y())};
}

// A rectangle (as FloorQuads makes them) grown by `by` on every side.
Quad Grown(const Quad& q, double by) {
  const Vector2d u = (q[1] - q[0]).normalized() * by;
  const Vector2d v = (q[3] - q[0]).normalized() * by;
  return {q[0] - u - v, q[1] + u - v, q[2] + u + v, q[3] - u + v};
}

// A rectangle centred on `center` with `along` metres along unit `tangent` and `across` metres
// along unit `normal`.
Quad Box(const Vector2d& center, const Vector2d& tangent, const Vector2d& normal, double along,
         double across) {
  const Vector2d t = 0.5 * along * tangent;
  const Vector2d n = 0.5 * across * normal;
  return {center - t - n, center + t - n, center + t + n, center - t + n};
}

// A wall's band: from its inner face outwards by `thickness`.
Quad WallBand(const Wall& wall, double thickness) {
  const Vector2d out = -wall.inward_normal * thickness;
  return {wall.start, wall.end, wall.end + out, wall.start + out};
}

// The opening of a doorway between the inner edges of its columns, from the corridor face
// through the wall to the room (or one wall thickness when there is no room).
struct DoorGeometry {
  Vector2d edge_a, edge_b;  // inner column edges on the corridor face
  Vector2d into_room;       // unit, -inward_normal
  double depth = 0.0;       // corridor face to room floor (m)
  Quad opening;
};

DoorGeometry DoorShape(const Doorway& door, double wall_thickness) {
  DoorGeometry g;
  const Vector2d ab = door.column_b - door.column_a;
  const Vector2d t =
      ab.norm() > 0.0 ? Vector2d(ab.normalized()) : Perpendicular(door.inward_normal);
  g.edge_a = door.column_a + t * 0.5 * door.column_width_m;
  g.edge_b = door.column_b - t * 0.5 * door.column_width_m;
  g.into_room = -door.inward_normal;
  g.depth = wall_thickness;
  if (door.room) {
    const Vector2d nearest =
        door.column_a.cwiseMax(door.room->footprint.min()).cwiseMin(door.room->footprint.max());
    const double to_room = (nearest - door.column_a).dot(g.into_room);
    if (to_room > 0.0 && to_room < 4.0 * wall_thickness) g.depth = to_room;
  }
  const Vector2d through = g.into_room * g.depth;
  g.opening = {g.edge_a, g.edge_b, g.edge_b + through, g.edge_a + through};
  return g;
}

Eigen::AlignedBox2d PlanExtent(const World& world) {
  const double wall = WallThicknessM(world);
  Eigen::AlignedBox2d box;
  const auto add_quad = [&](const Quad& q) {
    for (const Vector2d& p : q) box.extend(p);
  };
  for (const Quad& q : FloorQuads(world)) add_quad(Grown(q, wall));
  for (const Wall& w : world.walls) add_quad(WallBand(w, wall));
  for (const Doorway& door : world.doors) {
    add_quad(DoorShape(door, wall).opening);
    if (door.room) add_quad(Grown(door.room->footprint, wall));
  }
  for (const DoorPlate& plate : world.plates) box.extend(Vector2d(plate.center.head<2>()));
  for (const Lamp& lamp : world.lamps) {
    const Vector2d half = lamp.shape == LampShape::kCircular ? Vector2d::Constant(lamp.radius_m)
                                                             : Vector2d(0.5 * lamp.size_m);
    box.extend(Vector2d(lamp.center.head<2>() - half));
    box.extend(Vector2d(lamp.center.head<2>() + half));
  }
  for (const Reflector& r : world.reflectors) {
    box.extend(Vector2d(r.apparent_lamp_center.head<2>()));
  }
  for (const Distractor& d : world.distractors) box.extend(Vector2d(d.center.head<2>()));
  if (box.isEmpty()) box = Eigen::AlignedBox2d(Vector2d(-1, -1), Vector2d(1, 1));
  // A plan needs some area even for a degenerate world.
  const Vector2d pad = (Vector2d::Constant(1.0) - box.sizes()).cwiseMax(0.0) * 0.5;
  return Eigen::AlignedBox2d(box.min() - pad, box.max() + pad);
}

// ---------------------------------------------------------------------------------------------
// Text (pixel coordinates)

struct TextStyle {
  double scale = kTextScale;
  int thickness = 1;
  cv::Scalar color = kText;
  bool halo = false;  // a white outline keeps text readable over shapes
};

cv::Size TextSize(const std::string& text, const TextStyle& style) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, style.scale, style.thickness, &baseline);
}

// `origin` is the left end of the baseline, as in cv::putText.
void DrawText(cv::Mat& canvas, const std::string& text, cv::Point origin, const TextStyle& style) {
  if (style.halo) {
    cv::putText(canvas, text, origin, kFont, style.scale, kWhite, style.thickness + 3, cv::LINE_AA);
  }
  cv::putText(canvas, text, origin, kFont, style.scale, style.color, style.thickness, cv::LINE_AA);
}

void DrawTextCentered(cv::Mat& canvas, const std::string& text, const Vector2d& center_px,
                      const TextStyle& style) {
  const cv::Size size = TextSize(text, style);
  DrawText(canvas, text, Rounded(center_px + Vector2d(-0.5 * size.width, 0.5 * size.height)),
           style);
}

// Centre of a text box placed beside `anchor_px`, `gap_px` away in pixel direction `dir_px`.
Vector2d BesideCenter(const Vector2d& anchor_px, const Vector2d& dir_px, cv::Size size,
                      double gap_px) {
  const Vector2d d = dir_px.normalized();
  const double half = std::abs(d.x()) * 0.5 * size.width + std::abs(d.y()) * 0.5 * size.height;
  return anchor_px + d * (gap_px + half);
}

// Greedy word wrap of `pieces` joined by `separator` into lines at most `max_width_px` wide.
std::vector<std::string> Wrap(const std::vector<std::string>& pieces, const std::string& separator,
                              const TextStyle& style, int max_width_px) {
  std::vector<std::string> lines;
  std::string line;
  for (const std::string& piece : pieces) {
    const std::string longer = line.empty() ? piece : line + separator + piece;
    if (!line.empty() && TextSize(longer, style).width > max_width_px) {
      lines.push_back(line);
      line = piece;
    } else {
      line = longer;
    }
  }
  if (!line.empty()) lines.push_back(line);
  return lines;
}

std::string Format(const char* format, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), format, value);
  return buffer;
}

// ---------------------------------------------------------------------------------------------
// Layout: title block, plan, legend block, top to bottom

struct TitleLine {
  std::string text;
  TextStyle style;
};

struct LegendEntry {
  int width_px = 0;
  std::function<void(cv::Mat&, cv::Point)> draw;  // at the top-left of its row cell
};

struct PlanLayout {
  MapView view;
  std::vector<TitleLine> title;
  std::vector<LegendEntry> legend;
  std::vector<cv::Point> legend_at;
  cv::Rect legend_box;
};

double AutoPxPerM(const Eigen::AlignedBox2d& extent) {
  const double longest_m = extent.sizes().maxCoeff();
  const double preferred =
      std::clamp(kTargetLongestSidePx / longest_m, kMinAutoPxPerM, kMaxAutoPxPerM);
  // Very long worlds (a 1 km corridor) get a coarser plan rather than no plan.
  return std::min(preferred, 0.8 * kMaxSidePx / longest_m);
}

// Largest "nice" length whose bar fits in `max_px`.
double ScaleBarLengthM(double px_per_m, double max_px) {
  double best = 0.1;
  for (const double length : {0.1, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0}) {
    if (length * px_per_m <= max_px) best = length;
  }
  return best;
}

std::vector<TitleLine> TitleLines(const World& world, double px_per_m, int max_width_px) {
  int open = 0, closed = 0, empty = 0, lamps_off = 0;
  for (const Doorway& door : world.doors) {
    open += door.state == DoorState::kOpen ? 1 : 0;
    closed += door.state == DoorState::kClosed ? 1 : 0;
    empty += door.state == DoorState::kEmpty ? 1 : 0;
  }
  for (const Lamp& lamp : world.lamps) lamps_off += lamp.on ? 0 : 1;
  const auto n = [](std::size_t count) { return std::to_string(count); };

  const TextStyle heading{kTitleScale, 2, kText, false};
  const TextStyle body{kTextScale, 1, kText, false};
  std::vector<TitleLine> lines;
  for (const std::string& text :
       Wrap({"corridorsim world", "layout " + LayoutName(world.options.layout),
             "seed " + std::to_string(world.seed), Format("%.1f px/m", px_per_m)},
            "  |  ", heading, max_width_px)) {
    lines.push_back({text, heading});
  }
  const std::vector<std::string> counts = {
      n(world.segments.size()) + " corridor segments",
      n(world.doors.size()) + " doors (" + n(open) + " open, " + n(closed) + " closed, " +
          n(empty) + " empty)",
      n(world.plates.size()) + " door plates",
      n(world.lamps.size()) + " lamps (" + n(lamps_off) + " off)",
      n(world.reflectors.size()) + " reflectors",
      n(world.distractors.size()) + " distractors",
      n(world.corner_points.size()) + " corner points",
      n(world.triangle_count()) + " triangles"};
  for (const std::string& text : Wrap(counts, ",  ", body, max_width_px)) {
    lines.push_back({text, body});
  }
  return lines;
}

int TitleHeight(const std::vector<TitleLine>& lines) {
  int height = kPadPx;
  for (const TitleLine& line : lines) height += TextSize(line.text, line.style).height + 10;
  return height + kPadPx;
}

// A legend entry: a 28x14 px swatch drawn by `swatch` (given its centre) and a label.
LegendEntry SwatchEntry(const std::string& label, std::function<void(cv::Mat&, cv::Point)> swatch) {
  const TextStyle style;
  const cv::Size size = TextSize(label, style);
  LegendEntry entry;
  entry.width_px = 36 + size.width + 22;
  entry.draw = [label, swatch, size, style](cv::Mat& canvas, cv::Point top_left) {
    const cv::Point center = top_left + cv::Point(14, kLegendRowPx / 2);
    swatch(canvas, center);
    DrawText(canvas, label, top_left + cv::Point(36, kLegendRowPx / 2 + size.height / 2), style);
  };
  return entry;
}

void SwatchRect(cv::Mat& canvas, cv::Point center, cv::Size size, const cv::Scalar& fill,
                const cv::Scalar& edge) {
  const cv::Rect rect(center.x - size.width / 2, center.y - size.height / 2, size.width,
                      size.height);
  cv::rectangle(canvas, rect, fill, cv::FILLED, cv::LINE_AA);
  cv::rectangle(canvas, rect, edge, 1, cv::LINE_AA);
}

std::vector<LegendEntry> LegendEntries(double px_per_m, int canvas_width) {
  std::vector<LegendEntry> entries;
  const TextStyle style;

  // Scale bar: black and white halves with the length written after it.
  const double bar_m = ScaleBarLengthM(px_per_m, std::min(400.0, 0.3 * canvas_width));
  const int bar_px = std::max(1, cvRound(bar_m * px_per_m));
  const std::string bar_label = bar_m >= 1.0 ? Format("%.0f m", bar_m) : Format("%.1f m", bar_m);
  const cv::Size bar_label_size = TextSize(bar_label, style);
  entries.push_back({bar_px + 8 + bar_label_size.width + 22, [=](cv::Mat& canvas, cv::Point at) {
                       const int y = at.y + kLegendRowPx / 2;
                       const int half = bar_px / 2;
                       cv::rectangle(canvas, cv::Rect(at.x, y - 4, half, 8), kBlack, cv::FILLED);
                       cv::rectangle(canvas, cv::Rect(at.x + half, y - 4, bar_px - half, 8), kWhite,
                                     cv::FILLED);
                       cv::rectangle(canvas, cv::Rect(at.x, y - 4, bar_px, 8), kBlack, 1);
                       DrawText(canvas, bar_label,
                                cv::Point(at.x + bar_px + 8, y + bar_label_size.height / 2), style);
                     }});

  // Axes of frame W as drawn: +x right, +y up.
  entries.push_back(
      {80, [=](cv::Mat& canvas, cv::Point at) {
         const cv::Point o = at + cv::Point(4, kLegendRowPx - 4);
         cv::arrowedLine(canvas, o, o + cv::Point(26, 0), kText, 2, cv::LINE_AA, 0, 0.3);
         cv::arrowedLine(canvas, o, o + cv::Point(0, -22), kText, 2, cv::LINE_AA, 0, 0.3);
         DrawText(canvas, "x", o + cv::Point(30, 4), style);
         DrawText(canvas, "y", o + cv::Point(9, -12), style);
       }});

  const cv::Size swatch(28, 14);
  entries.push_back(SwatchEntry(
      "corridor", [=](cv::Mat& c, cv::Point p) { SwatchRect(c, p, swatch, kFloor, kFloor); }));
  entries.push_back(SwatchEntry(
      "room", [=](cv::Mat& c, cv::Point p) { SwatchRect(c, p, swatch, kRoomFloor, kRoomFloor); }));
  entries.push_back(SwatchEntry("wall", [=](cv::Mat& c, cv::Point p) {
    SwatchRect(c, p, cv::Size(28, 6), kWallColor, kWallColor);
  }));
  entries.push_back(SwatchEntry("closed door", [=](cv::Mat& c, cv::Point p) {
    SwatchRect(c, p, cv::Size(28, 6), kClosed, kClosed);
  }));
  entries.push_back(SwatchEntry("open door + leaf", [=](cv::Mat& c, cv::Point p) {
    SwatchRect(c, p + cv::Point(0, -4), cv::Size(28, 6), kOpen, kOpen);
    cv::line(c, p + cv::Point(-13, -1), p + cv::Point(-13, 8), kOpen, 2, cv::LINE_AA);
  }));
  entries.push_back(SwatchEntry("empty doorway", [=](cv::Mat& c, cv::Point p) {
    SwatchRect(c, p, cv::Size(28, 6), kEmpty, kEmpty);
  }));
  entries.push_back(SwatchEntry("door plate + room no.", [=](cv::Mat& c, cv::Point p) {
    SwatchRect(c, p, cv::Size(14, 8), kWhite, kBlack);
  }));
  entries.push_back(SwatchEntry("lamp", [=](cv::Mat& c, cv::Point p) {
    cv::circle(c, p, 6, kLampOn, cv::FILLED, cv::LINE_AA);
    cv::circle(c, p, 6, kLampOnEdge, 1, cv::LINE_AA);
  }));
  entries.push_back(SwatchEntry("panel lamp", [=](cv::Mat& c, cv::Point p) {
    SwatchRect(c, p, cv::Size(24, 8), kLampOn, kLampOnEdge);
  }));
  entries.push_back(SwatchEntry("lamp off", [=](cv::Mat& c, cv::Point p) {
    cv::circle(c, p, 6, kLampOff, cv::FILLED, cv::LINE_AA);
    cv::circle(c, p, 6, kLampOffEdge, 1, cv::LINE_AA);
  }));
  entries.push_back(SwatchEntry("reflector (o: mirrored lamp)", [=](cv::Mat& c, cv::Point p) {
    cv::line(c, p + cv::Point(-13, -4), p + cv::Point(13, -4), kReflector, 3, cv::LINE_AA);
    cv::circle(c, p + cv::Point(0, 4), 4, kReflector, 1, cv::LINE_AA);
  }));
  entries.push_back(SwatchEntry(
      "distractor: P poster, N notice board, B bookshelf, C cabinet, F extinguisher",
      [=](cv::Mat& c, cv::Point p) {
        SwatchRect(c, p, cv::Size(18, 12), kDistractor, kDistractorEdge);
        DrawTextCentered(c, "P", Vector2d(p.x, p.y), TextStyle{kTagScale, 1, kText, false});
      }));
  return entries;
}

PlanLayout ComputeLayout(const World& world, double px_per_m) {
  if (!std::isfinite(px_per_m)) throw std::invalid_argument("RenderMap: px_per_m is not finite");
  const Eigen::AlignedBox2d extent = PlanExtent(world);
  const double scale = px_per_m > 0.0 ? px_per_m : AutoPxPerM(extent);
  const double plan_w = std::ceil(extent.sizes().x() * scale);
  const double plan_h = std::ceil(extent.sizes().y() * scale);
  if (plan_w + 2 * kMarginPx > kMaxSidePx || plan_h + 2 * kMarginPx > kMaxSidePx) {
    throw std::invalid_argument(Format("RenderMap: %.3f px/m makes the map larger than ", scale) +
                                std::to_string(kMaxSidePx) + " px on a side");
  }
  PlanLayout layout;
  const int width = std::max(static_cast<int>(plan_w) + 2 * kMarginPx, kMinCanvasWidthPx);
  layout.title = TitleLines(world, scale, width - 2 * kPadPx);
  const int title_h = TitleHeight(layout.title);

  // Legend: entries flow left to right and wrap at the canvas width.
  layout.legend = LegendEntries(scale, width);
  const int legend_top = title_h + static_cast<int>(plan_h) + 2 * kMarginPx;
  cv::Point at(2 * kPadPx, legend_top + kPadPx);
  for (const LegendEntry& entry : layout.legend) {
    if (at.x > 2 * kPadPx && at.x + entry.width_px > width - 2 * kPadPx) {
      at = cv::Point(2 * kPadPx, at.y + kLegendRowPx);
    }
    layout.legend_at.push_back(at);
    at.x += entry.width_px;
  }
  const int legend_bottom = at.y + kLegendRowPx + kPadPx;
  layout.legend_box = cv::Rect(kPadPx, legend_top, width - 2 * kPadPx, legend_bottom - legend_top);

  MapView& view = layout.view;
  view.px_per_m = scale;
  view.min_in_world = extent.min();
  view.min_px = Vector2d(0.5 * (width - plan_w), title_h + kMarginPx + plan_h);
  view.width_px = width;
  view.height_px = legend_bottom + kPadPx;
  return layout;
}

// ---------------------------------------------------------------------------------------------
// Drawing the plan (world coordinates)

class Painter {
 public:
  Painter(cv::Mat& canvas, const MapView& view) : canvas_(canvas), view_(view) {}

  Vector2d Px(const Vector2d& p_in_world) const { return view_.ToPixel(p_in_world); }
  // `m` metres, but at least `min_px` pixels, in metres.
  double AtLeast(double m, double min_px) const { return std::max(m, min_px / view_.px_per_m); }

  void Fill(const Quad& quad, const cv::Scalar& color) {
    std::array<cv::Point, 4> points;
    for (std::size_t i = 0; i < 4; ++i) points[i] = Fixed(Px(quad[i]));
    cv::fillConvexPoly(canvas_, points.data(), 4, color, cv::LINE_AA, kShift);
  }
  void Outline(const Quad& quad, const cv::Scalar& color, int thickness_px) {
    std::array<cv::Point, 4> points;
    for (std::size_t i = 0; i < 4; ++i) points[i] = Fixed(Px(quad[i]));
    const cv::Point* polygon = points.data();
    const int count = 4;
    cv::polylines(canvas_, &polygon, &count, 1, true, color, thickness_px, cv::LINE_AA, kShift);
  }
  void Line(const Vector2d& a, const Vector2d& b, const cv::Scalar& color, int thickness_px) {
    cv::line(canvas_, Fixed(Px(a)), Fixed(Px(b)), color, thickness_px, cv::LINE_AA, kShift);
  }
  void Polyline(const std::vector<Vector2d>& points_in_world, const cv::Scalar& color,
                int thickness_px) {
    std::vector<cv::Point> points;
    for (const Vector2d& p : points_in_world) points.push_back(Fixed(Px(p)));
    cv::polylines(canvas_, points, false, color, thickness_px, cv::LINE_AA, kShift);
  }
  // thickness_px < 0 fills.
  void Circle(const Vector2d& center, double radius_m, const cv::Scalar& color, int thickness_px) {
    const double radius_px = std::max(radius_m * view_.px_per_m, 2.0);
    cv::circle(canvas_, Fixed(Px(center)), cvRound(radius_px * kSubpixel), color, thickness_px,
               cv::LINE_AA, kShift);
  }
  // Text centred beside the world point `anchor`, in world direction `direction`.
  void TextBeside(const std::string& text, const Vector2d& anchor, const Vector2d& direction,
                  double gap_px, const TextStyle& style) {
    const Vector2d center = BesideCenter(Px(anchor), MapView::DirectionToPixel(direction),
                                         TextSize(text, style), gap_px);
    DrawTextCentered(canvas_, text, center, style);
  }

 private:
  cv::Mat& canvas_;
  const MapView& view_;
};

char DistractorTag(SemanticClass c) {
  switch (c) {
    case SemanticClass::kPoster:
      return 'P';
    case SemanticClass::kNoticeBoard:
      return 'N';
    case SemanticClass::kBookshelf:
      return 'B';
    case SemanticClass::kCabinet:
      return 'C';
    case SemanticClass::kFireExtinguisher:
      return 'F';
    default:
      return '?';
  }
}

// Rooms, then the corridor: wall mass (each floor area grown by the wall thickness) under the
// floors gives closed corners; the listed walls are drawn on top where they really are.
void DrawStructure(Painter& paint, const World& world, double wall) {
  for (const Doorway& door : world.doors) {
    if (door.room) paint.Fill(Grown(door.room->footprint, wall), kWallColor);
  }
  const std::vector<Quad> floors = FloorQuads(world);
  for (const Quad& q : floors) paint.Fill(Grown(q, wall), kWallColor);
  for (const Wall& w : world.walls) paint.Fill(WallBand(w, wall), kWallColor);
  for (const Doorway& door : world.doors) {
    if (door.room) paint.Fill(Grown(door.room->footprint, 0.0), kRoomFloor);
  }
  for (const Quad& q : floors) paint.Fill(q, kFloor);
}

void DrawDoors(Painter& paint, const World& world, double wall) {
  for (const Doorway& door : world.doors) {
    const DoorGeometry g = DoorShape(door, wall);
    const cv::Scalar& color = door.state == DoorState::kClosed ? kClosed
                              : door.state == DoorState::kOpen ? kOpen
                                                               : kEmpty;
    paint.Fill(g.opening, color);
    if (door.state == DoorState::kOpen) {
      // Leaf hinged at column a's edge on the room side, swung 90 degrees into the room, and
      // the arc its free end sweeps.
      const Vector2d hinge = g.edge_a + g.into_room * g.depth;
      const Vector2d closed_dir = g.edge_b - g.edge_a;
      const double length = closed_dir.norm();
      if (length > 0.0) {
        paint.Line(hinge, hinge + g.into_room * length, kOpen, 3);
        std::vector<Vector2d> arc;
        const Vector2d u = closed_dir / length;
        for (int k = 0; k <= 16; ++k) {
          const double angle = 0.5 * std::numbers::pi * k / 16.0;
          arc.push_back(hinge + length * (std::cos(angle) * u + std::sin(angle) * g.into_room));
        }
        paint.Polyline(arc, kOpen, 1);
      }
    }
    const Vector2d t = (door.column_b - door.column_a).normalized();
    const double side = paint.AtLeast(door.column_width_m, 4.0);
    for (const Vector2d& column : {door.column_a, door.column_b}) {
      paint.Fill(Box(column, t, door.inward_normal, side, side), kColumn);
    }
  }
}

void DrawLamps(Painter& paint, const World& world) {
  for (const Lamp& lamp : world.lamps) {
    const Vector2d center = lamp.center.head<2>();
    const cv::Scalar& fill = lamp.on ? kLampOn : kLampOff;
    const cv::Scalar& edge = lamp.on ? kLampOnEdge : kLampOffEdge;
    if (lamp.shape == LampShape::kCircular) {
      paint.Circle(center, lamp.radius_m, fill, cv::FILLED);
      paint.Circle(center, lamp.radius_m, edge, 1);
    } else {
      const Quad quad =
          Box(center, Vector2d::UnitX(), Vector2d::UnitY(), lamp.size_m.x(), lamp.size_m.y());
      paint.Fill(quad, fill);
      paint.Outline(quad, edge, 1);
    }
  }
}

void DrawReflectors(Painter& paint, const World& world, const std::map<int, const Wall*>& walls) {
  std::map<int, const Lamp*> lamps;
  for (const Lamp& lamp : world.lamps) lamps[lamp.id] = &lamp;
  for (const Reflector& r : world.reflectors) {
    if (const auto wall = walls.find(r.wall_id); wall != walls.end()) {
      const Vector2d t = wall->second->tangent();
      const Vector2d c =
          Vector2d(r.center.head<2>()) + wall->second->inward_normal * paint.AtLeast(0.0, 2.0);
      paint.Line(c - 0.5 * r.size_m.x() * t, c + 0.5 * r.size_m.x() * t, kReflector, 4);
    }
    const auto lamp = lamps.find(r.mirrored_lamp_id);
    const double radius = lamp != lamps.end() ? lamp->second->radius_m : 0.2;
    paint.Circle(r.apparent_lamp_center.head<2>(), radius, kReflector, 2);
  }
}

void DrawDistractors(Painter& paint, const World& world) {
  const TextStyle tag{kTagScale, 1, kText, true};
  for (const Distractor& d : world.distractors) {
    const Vector2d n = d.normal.head<2>().normalized();
    const Vector2d t = -Perpendicular(n);
    const Vector2d center = d.center.head<2>();
    const double across = paint.AtLeast(d.size_m.y(), 4.0);
    const Quad quad = Box(center, t, n, paint.AtLeast(d.size_m.x(), 6.0), across);
    paint.Fill(quad, kDistractor);
    paint.Outline(quad, kDistractorEdge, 1);
    paint.TextBeside(std::string(1, DistractorTag(d.semantic_class)), center + n * 0.5 * across, n,
                     3.0, tag);
  }
}

// Plates stand on the wall face into the corridor; their numbers go outside the wall.
void DrawPlates(Painter& paint, const World& world, double wall) {
  const TextStyle label{kLabelScale, 1, kBlack, true};
  for (const DoorPlate& plate : world.plates) {
    const Vector2d n = plate.normal.head<2>().normalized();
    const Vector2d t = -Perpendicular(n);
    const double depth = paint.AtLeast(0.04, 5.0);
    const Vector2d face = plate.center.head<2>();
    const Quad quad =
        Box(face + n * 0.5 * depth, t, n, paint.AtLeast(plate.size_m.x(), 6.0), depth);
    paint.Fill(quad, kWhite);
    paint.Outline(quad, kBlack, 1);
    if (!plate.room_number.empty()) {
      paint.TextBeside(plate.room_number, face - n * paint.AtLeast(wall, 3.0), -n, 4.0, label);
    }
  }
}

void DrawTitleAndLegend(cv::Mat& canvas, const PlanLayout& layout) {
  int y = kPadPx;
  for (const TitleLine& line : layout.title) {
    y += TextSize(line.text, line.style).height;
    DrawText(canvas, line.text, cv::Point(kPadPx, y), line.style);
    y += 10;
  }
  cv::rectangle(canvas, layout.legend_box, Rgb(120, 120, 120), 1, cv::LINE_AA);
  for (std::size_t i = 0; i < layout.legend.size(); ++i) {
    layout.legend[i].draw(canvas, layout.legend_at[i]);
  }
}

}  // namespace

MapView ComputeMapView(const World& world, double px_per_m) {
  return ComputeLayout(world, px_per_m).view;
}

Image8 RenderMap(const World& world, double px_per_m) {
  const PlanLayout layout = ComputeLayout(world, px_per_m);
  const MapView& view = layout.view;
  cv::Mat canvas(view.height_px, view.width_px, CV_8UC3, kWhite);
  Painter paint(canvas, view);
  const double wall = paint.AtLeast(WallThicknessM(world), 3.0);
  std::map<int, const Wall*> walls;
  for (const Wall& w : world.walls) walls[w.id] = &w;

  DrawStructure(paint, world, wall);
  DrawDoors(paint, world, wall);
  DrawLamps(paint, world);
  DrawReflectors(paint, world, walls);
  DrawDistractors(paint, world);
  DrawPlates(paint, world, wall);
  DrawTitleAndLegend(canvas, layout);

  Image8 image(view.width_px, view.height_px, 3);
  for (int row = 0; row < canvas.rows; ++row) {
    std::copy_n(canvas.ptr<std::uint8_t>(row), std::size_t(canvas.cols) * 3, image.Pixel(0, row));
  }
  return image;
}

}  // namespace corridorsim::worlds
