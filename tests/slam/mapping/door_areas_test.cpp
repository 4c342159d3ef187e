// The map divided at the doors (P2 Fig. 12, slam/mapping/door_areas.h): rooms behind the doors'
// wall lines, on the side away from the robot, cut between neighbouring doors; landmarks by area.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <catch2/catch.hpp>

#include "slam/mapping/door_areas.h"

namespace corridorsim::slam {
namespace {

using Eigen::Vector2d;

// A corridor along x between walls y = +-1.2; the robot drives along y = 0.
AreaDoor Door(int id, double x0, double x1, double wall_y) {
  return {id, Vector2d(x0, wall_y), Vector2d(x1, wall_y), Vector2d(0.5 * (x0 + x1), 0.0)};
}

const MapArea* AreaOf(const std::vector<MapArea>& areas, int landmark) {
  for (const MapArea& a : areas) {
    if (std::count(a.landmark_ids.begin(), a.landmark_ids.end(), landmark)) return &a;
  }
  return nullptr;
}

double SignedArea(const std::vector<Vector2d>& polygon) {
  double area = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vector2d& a = polygon[i];
    const Vector2d& b = polygon[(i + 1) % polygon.size()];
    area += a.x() * b.y() - b.x() * a.y();
  }
  return 0.5 * area;
}

TEST_CASE("each door opens a room behind its wall, away from the robot", "[door_areas]") {
  DoorAreaOptions options;
  options.room_depth_m = 4.0;
  options.room_reach_m = 1.5;
  // Two doors in the left wall (y = 1.2) 3 m apart, one in the right wall (y = -1.2).
  const std::vector<AreaDoor> doors = {Door(10, 2.0, 3.0, 1.2), Door(11, 6.0, 7.0, 1.2),
                                       Door(12, 4.0, 5.0, -1.2)};
  const std::vector<AreaPoint> points = {
      {1, Vector2d(2.5, 3.0)},   // behind door 10
      {2, Vector2d(6.4, 4.9)},   // behind door 11
      {3, Vector2d(4.5, -2.0)},  // behind door 12
      {4, Vector2d(4.0, 0.3)},   // the corridor
      {5, Vector2d(2.5, 1.25)},  // on door 10's line: the doorway, the corridor's
      {6, Vector2d(4.4, 2.0)},   // between doors 10 and 11, nearer 10's edge (3.0) than 11's
      {7, Vector2d(4.6, 2.0)},   // ... nearer 11's edge (6.0): the cut is half-way, at 4.5
      {8, Vector2d(2.5, 5.5)},   // deeper than room_depth_m
      {9, Vector2d(std::numeric_limits<double>::quiet_NaN(), 0.0)},
  };
  const std::vector<MapArea> areas = DivideAtDoors(doors, points, options);
  REQUIRE(areas.size() == 4);
  CHECK(areas[0].kind == AreaKind::kCorridor);
  CHECK(areas[0].id == 0);
  CHECK(areas[0].polygon.empty());
  for (int k = 1; k <= 3; ++k) {
    CHECK(areas[k].id == k);
    CHECK(areas[k].kind == AreaKind::kRoom);
    CHECK(areas[k].door_landmark_id == doors[k - 1].landmark_id);
    REQUIRE(areas[k].polygon.size() == 4);
    CHECK(SignedArea(areas[k].polygon) > 0);  // counter-clockwise
  }
  CHECK(AreaOf(areas, 1) == &areas[1]);
  CHECK(AreaOf(areas, 2) == &areas[2]);
  CHECK(AreaOf(areas, 3) == &areas[3]);
  CHECK(AreaOf(areas, 4) == &areas[0]);
  CHECK(AreaOf(areas, 5) == &areas[0]);
  CHECK(AreaOf(areas, 6) == &areas[1]);
  CHECK(AreaOf(areas, 7) == &areas[2]);
  CHECK(AreaOf(areas, 8) == &areas[0]);
  CHECK(AreaOf(areas, 9) == nullptr);  // not finite: in no area
  // Room 1 spans x from 2 - 1.5 = 0.5 to the cut at 4.5, y from the wall to 4 m behind it;
  // room 3 lies on the other side of the corridor.
  double x_min = 1e9, x_max = -1e9, y_min = 1e9, y_max = -1e9;
  for (const Vector2d& p : areas[1].polygon) {
    x_min = std::min(x_min, p.x()), x_max = std::max(x_max, p.x());
    y_min = std::min(y_min, p.y()), y_max = std::max(y_max, p.y());
  }
  CHECK(x_min == Approx(0.5));
  CHECK(x_max == Approx(4.5));
  CHECK(y_min == Approx(1.2));
  CHECK(y_max == Approx(5.2));
  for (const Vector2d& p : areas[3].polygon) CHECK(p.y() <= -1.2 + 1e-9);
  // Landmark ids ascending in each area.
  for (const MapArea& a : areas)
    CHECK(std::is_sorted(a.landmark_ids.begin(), a.landmark_ids.end()));
}

TEST_CASE("the room side follows the robot, whichever column comes first", "[door_areas]") {
  // The same door with its columns swapped, and the robot on either side.
  for (const bool swap : {false, true}) {
    for (const double robot_y : {-1.0, 3.0}) {
      AreaDoor door{7, Vector2d(0, 1.2), Vector2d(1, 1.2), Vector2d(0.5, robot_y)};
      if (swap) std::swap(door.column_a, door.column_b);
      const std::vector<MapArea> areas =
          DivideAtDoors({door}, {{1, Vector2d(0.5, 2.5)}, {2, Vector2d(0.5, 0.0)}});
      REQUIRE(areas.size() == 2);
      CHECK(SignedArea(areas[1].polygon) > 0);
      const bool room_above = robot_y < 1.2;
      INFO("swap " << swap << " robot y " << robot_y);
      CHECK(AreaOf(areas, 1) == &areas[room_above ? 1 : 0]);
      CHECK(AreaOf(areas, 2) == &areas[room_above ? 0 : 1]);
    }
  }
}

TEST_CASE("tilted door lines are squared to the directions the doors agree on", "[door_areas]") {
  // Three doors in walls along x, one tilted by 8 deg (its columns' bearing-only estimates): with
  // `manhattan` its room is square to the others'; without, it keeps its tilt.
  const double tilt = 8.0 * std::numbers::pi / 180.0;
  AreaDoor tilted = Door(3, 10.0, 11.0, 1.2);
  tilted.column_b = tilted.column_a + Vector2d(std::cos(tilt), std::sin(tilt));
  const std::vector<AreaDoor> doors = {Door(1, 2.0, 3.0, 1.2), Door(2, 5.0, 6.0, -1.2), tilted};
  const auto edge_angle = [](const MapArea& room) {
    const Vector2d d = room.polygon[1] - room.polygon[0];
    return std::atan2(d.y(), d.x());
  };
  DoorAreaOptions options;
  const std::vector<MapArea> squared = DivideAtDoors(doors, {}, options);
  REQUIRE(squared.size() == 4);
  // The agreed direction is the width-weighted circular mean modulo 90 deg (of four times the
  // angles): the tilted door pulls it by about a third of its tilt.
  const double agreed = 0.25 * std::atan2(std::sin(4 * tilt), 2.0 + std::cos(4 * tilt));
  CHECK(agreed == Approx(tilt / 3.0).epsilon(0.02));
  for (int k = 1; k <= 3; ++k) {
    const double a = std::remainder(edge_angle(squared[k]) - agreed, 0.5 * std::numbers::pi);
    CHECK(std::abs(a) < 1e-9);
  }
  options.manhattan = false;
  const std::vector<MapArea> own = DivideAtDoors(doors, {}, options);
  CHECK(std::abs(std::remainder(edge_angle(own[3]) - tilt, 0.5 * std::numbers::pi)) < 1e-9);
  CHECK(std::abs(std::remainder(edge_angle(own[1]), 0.5 * std::numbers::pi)) < 1e-9);
  // A door further than max_turn_deg from the agreed directions keeps its own line.
  options.manhattan = true;
  options.max_turn_deg = 2.0;
  const std::vector<MapArea> kept = DivideAtDoors(doors, {}, options);
  CHECK(std::abs(std::remainder(edge_angle(kept[3]) - tilt, 0.5 * std::numbers::pi)) < 1e-9);
}

TEST_CASE("a degenerate door opens no room", "[door_areas]") {
  // Coinciding columns; a robot on the wall line (no side); a non-finite robot position.
  const std::vector<AreaDoor> doors = {
      {1, Vector2d(2, 1.2), Vector2d(2, 1.2), Vector2d(2, 0)},
      {2, Vector2d(4, 1.2), Vector2d(5, 1.2), Vector2d(7, 1.2)},
      {3, Vector2d(8, 1.2), Vector2d(9, 1.2), Vector2d(std::numeric_limits<double>::infinity(), 0)},
      Door(4, 11.0, 12.0, 1.2)};
  const std::vector<MapArea> areas = DivideAtDoors(doors, {{5, Vector2d(11.5, 2.0)}});
  REQUIRE(areas.size() == 2);
  CHECK(areas[1].door_landmark_id == 4);
  CHECK(areas[1].landmark_ids == std::vector<int>{5});
  CHECK(DivideAtDoors({}, {{5, Vector2d(1, 1)}}).size() == 1);
}

TEST_CASE("area options are bounded", "[door_areas]") {
  DoorAreaOptions options;
  CHECK_FALSE(options.Check());
  options.room_depth_m = 0.1;
  options.min_depth_m = 0.2;
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "room_depth_m");
  options = {};
  options.max_turn_deg = 60;
  REQUIRE(options.Check());
  CHECK(options.Check()->key == "max_turn_deg");
}

}  // namespace
}  // namespace corridorsim::slam
