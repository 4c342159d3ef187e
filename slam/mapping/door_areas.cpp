#include "slam/mapping/door_areas.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

namespace corridorsim::slam {
namespace {

using Eigen::Vector2d;

// A door's frame: origin at its midpoint, t along the wall from column a to b, n into the room.
struct RoomFrame {
  int door_index = 0;
  Vector2d origin;
  Vector2d t;
  Vector2d n;
  double half_width = 0.0;
  double lo = 0.0, hi = 0.0;  // the room's extent along t
};

std::optional<RoomFrame> FrameOf(const AreaDoor& door, int index, const DoorAreaOptions& o) {
  const Vector2d ab = door.column_b - door.column_a;
  const double width = ab.norm();
  if (!(width > 1e-6) || !door.robot_xy.allFinite()) return std::nullopt;
  RoomFrame f;
  f.door_index = index;
  f.origin = 0.5 * (door.column_a + door.column_b);
  f.t = ab / width;
  f.n = Vector2d(-f.t.y(), f.t.x());
  const double robot_side = (door.robot_xy - f.origin).dot(f.n);
  if (!(std::abs(robot_side) > 1e-6)) return std::nullopt;
  if (robot_side > 0) f.n = -f.n;  // the room lies away from the robot
  f.half_width = 0.5 * width;
  f.lo = -f.half_width - o.room_reach_m;
  f.hi = f.half_width + o.room_reach_m;
  return f;
}

}  // namespace

std::optional<OptionsProblem> DoorAreaOptions::Check() const {
  if (auto p = CheckOptionBounds(DoorAreaOptionsTable(), *this)) return p;
  if (!(room_depth_m > min_depth_m)) {
    return OptionsProblem{"room_depth_m", "must be above min_depth_m"};
  }
  return std::nullopt;
}

std::vector<MapArea> DivideAtDoors(const std::vector<AreaDoor>& doors,
                                   const std::vector<AreaPoint>& points,
                                   const DoorAreaOptions& options) {
  std::vector<RoomFrame> rooms;
  for (std::size_t i = 0; i < doors.size(); ++i) {
    if (auto f = FrameOf(doors[i], static_cast<int>(i), options)) rooms.push_back(*f);
  }
  if (options.manhattan && !rooms.empty()) {
    // The mean direction modulo 90 deg: the doors' angles times four, averaged as unit vectors
    // weighted by the door's width.
    Vector2d sum = Vector2d::Zero();
    for (const RoomFrame& f : rooms) {
      const double a = 4.0 * std::atan2(f.t.y(), f.t.x());
      sum += 2.0 * f.half_width * Vector2d(std::cos(a), std::sin(a));
    }
    if (sum.norm() > 1e-9) {
      const double axis = 0.25 * std::atan2(sum.y(), sum.x());
      const double max_turn = options.max_turn_deg * std::numbers::pi / 180.0;
      for (RoomFrame& f : rooms) {
        const double a = std::atan2(f.t.y(), f.t.x());
        // The nearest of axis + k * 90 deg.
        const double k = std::round((a - axis) / (0.5 * std::numbers::pi));
        const double snapped = axis + k * 0.5 * std::numbers::pi;
        if (std::abs(snapped - a) > max_turn) continue;
        const Vector2d t(std::cos(snapped), std::sin(snapped));
        f.n = f.n.dot(Vector2d(-t.y(), t.x())) >= 0 ? Vector2d(-t.y(), t.x())
                                                    : Vector2d(t.y(), -t.x());
        f.t = t;
      }
    }
  }
  // Doors in the same wall (parallel, same room side, on one line within 0.5 m) split the wall
  // half-way between their nearest edges.
  for (RoomFrame& a : rooms) {
    for (const RoomFrame& b : rooms) {
      if (&a == &b || a.n.dot(b.n) < std::cos(0.2)) continue;
      const Vector2d d = b.origin - a.origin;
      if (std::abs(d.dot(a.n)) > 0.5) continue;
      const double along = d.dot(a.t);
      if (along > 0) {
        a.hi = std::min(a.hi, std::max(a.half_width, 0.5 * (along + a.half_width - b.half_width)));
      } else {
        a.lo = std::max(a.lo, std::min(-a.half_width, 0.5 * (along + b.half_width - a.half_width)));
      }
    }
  }
  std::vector<MapArea> areas(1);
  areas[0].id = 0;
  areas[0].kind = AreaKind::kCorridor;
  for (const RoomFrame& f : rooms) {
    MapArea room;
    room.id = static_cast<int>(areas.size());
    room.kind = AreaKind::kRoom;
    room.door_landmark_id = doors[static_cast<std::size_t>(f.door_index)].landmark_id;
    // Counter-clockwise: (t, n) is clockwise when n = -perp(t), so order the corners by sign.
    const bool ccw = f.t.x() * f.n.y() - f.t.y() * f.n.x() > 0;
    const Vector2d c0 = f.origin + f.lo * f.t, c1 = f.origin + f.hi * f.t;
    const Vector2d c2 = c1 + options.room_depth_m * f.n, c3 = c0 + options.room_depth_m * f.n;
    room.polygon =
        ccw ? std::vector<Vector2d>{c0, c1, c2, c3} : std::vector<Vector2d>{c0, c3, c2, c1};
    areas.push_back(std::move(room));
  }
  for (const AreaPoint& p : points) {
    if (!p.xy.allFinite()) continue;
    int best = 0;
    double best_distance = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < rooms.size(); ++k) {
      const RoomFrame& f = rooms[k];
      const Vector2d d = p.xy - f.origin;
      const double along = d.dot(f.t), depth = d.dot(f.n);
      if (depth < options.min_depth_m || depth > options.room_depth_m || along < f.lo ||
          along > f.hi) {
        continue;
      }
      const double distance = d.norm();
      if (distance < best_distance) best_distance = distance, best = static_cast<int>(k) + 1;
    }
    areas[static_cast<std::size_t>(best)].landmark_ids.push_back(p.landmark_id);
  }
  for (MapArea& a : areas) std::sort(a.landmark_ids.begin(), a.landmark_ids.end());
  return areas;
}

}  // namespace corridorsim::slam
