// Tests worlds/layout.cpp: the deterministic floor plan (segments, walls, floor cells, doors per
// wall) of every layout, and the problems it reports for doors that cannot fit.
#include "worlds/layout.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/tolerances.h"

#include "tests/support/expect_input_error.h"

namespace corridorsim::worlds {
namespace {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;
constexpr double kPlanTolM = test::kGeomTolM;  // plan coordinates are sums of options lengths

WorldOptions OptionsOf(Layout layout, double length_m, double second_length_m, int doors) {
  WorldOptions options;
  options.layout = layout;
  options.length_m = length_m;
  options.second_length_m = second_length_m;
  options.doors.count = doors;
  options.plates.count = std::min(options.plates.count, doors);
  return options;
}

LayoutPlan Plan(const WorldOptions& options, int first_id = 1) {
  LayoutPlan plan;
  const auto problem = PlanLayout(options, first_id, &plan);
  INFO((problem ? problem->key + ": " + problem->message : std::string("no problem")));
  REQUIRE_FALSE(problem);
  return plan;
}

// The problem PlanLayout reports for `options` (fails the test when it plans them).
OptionsProblem PlanProblem(const WorldOptions& options) {
  LayoutPlan plan;
  const std::optional<OptionsProblem> problem = PlanLayout(options, 1, &plan);
  REQUIRE(problem);
  return *problem;
}

bool InsideAnyCell(const LayoutPlan& plan, const Vector2d& p) {
  for (const AlignedBox2d& c : plan.floor_cells) {
    if (c.contains(p)) return true;
  }
  return false;
}

int SideWalls(const LayoutPlan& plan) {
  int n = 0;
  for (const Wall& w : plan.walls) n += w.side_wall ? 1 : 0;
  return n;
}

// The doorway capacity of a side wall: n footprints and n - 1 gaps in its usable length.
int Capacity(const Wall& wall, const WorldOptions& options, double footprint) {
  const double usable = UsableWallLength(wall, options);
  if (usable + kPlanTolM < footprint) return 0;
  return static_cast<int>(
             std::floor((usable - footprint) / (footprint + options.doors.min_gap_m) + 1e-9)) +
         1;
}

// The checks every plan must pass, whatever its layout.
void CheckPlanInvariants(const WorldOptions& options, const LayoutPlan& plan,
                         double corridor_area_m2) {
  REQUIRE(plan.segment_rects.size() == plan.segments.size());
  REQUIRE(plan.doors_per_wall.size() == plan.walls.size());

  // Inward normals are unit, on the left of start->end, and point into the corridor.
  for (const Wall& w : plan.walls) {
    INFO("wall " << w.id << " from (" << w.start.transpose() << ") to (" << w.end.transpose()
                 << ")");
    CHECK(w.length() > 0);
    CHECK(w.inward_normal.norm() == Approx(1.0).margin(kPlanTolM));
    CHECK(Vector2d(-w.tangent().y(), w.tangent().x()).dot(w.inward_normal) ==
          Approx(1.0).margin(kPlanTolM));
    const Vector2d mid = (w.start + w.end) / 2;
    CHECK(InsideAnyCell(plan, mid + 0.01 * w.inward_normal));
    CHECK_FALSE(InsideAnyCell(plan, mid - 0.01 * w.inward_normal));
  }

  // The walls form closed loops: every wall ends where exactly one other wall starts.
  for (const Wall& w : plan.walls) {
    int next = 0;
    for (const Wall& v : plan.walls) next += (v.start - w.end).norm() < kPlanTolM ? 1 : 0;
    CHECK(next == 1);
  }

  // Floor cells are disjoint and cover exactly the corridor's area.
  double area = 0.0;
  for (std::size_t i = 0; i < plan.floor_cells.size(); ++i) {
    const AlignedBox2d& a = plan.floor_cells[i];
    CHECK(a.volume() > 0);
    area += a.volume();
    for (std::size_t j = i + 1; j < plan.floor_cells.size(); ++j) {
      const AlignedBox2d overlap = a.intersection(plan.floor_cells[j]);
      CHECK((overlap.isEmpty() || overlap.volume() < kPlanTolM));
    }
  }
  CHECK(area == Approx(corridor_area_m2).margin(kPlanTolM));

  // Doorways: all allocated, only on side walls, each wall within its capacity.
  int total = 0;
  for (std::size_t k = 0; k < plan.walls.size(); ++k) {
    const Wall& w = plan.walls[k];
    INFO("wall " << w.id << " of length " << w.length() << " carries " << plan.doors_per_wall[k]);
    total += plan.doors_per_wall[k];
    CHECK(plan.doors_per_wall[k] >= 0);
    if (!w.side_wall) CHECK(plan.doors_per_wall[k] == 0);
    CHECK(plan.doors_per_wall[k] <= Capacity(w, options, plan.door_footprint_m));
  }
  CHECK(total == options.doors.count);
  CHECK(plan.door_footprint_m ==
        Approx(options.doors.width_m + 2 * options.doors.frame_width_m).margin(kPlanTolM));
}

TEST_CASE("a straight corridor has one segment, two side walls and two end caps",
          "[worlds][layout]") {
  const WorldOptions options;  // defaults: 55 m x 2.4 m, 16 doors
  const LayoutPlan plan = Plan(options);
  REQUIRE(plan.segments.size() == 1);
  CHECK(plan.segments[0].start.isApprox(Vector2d(0, 0)));
  CHECK(plan.segments[0].end.isApprox(Vector2d(55, 0)));
  CHECK(plan.segments[0].width_m == options.width_m);
  CHECK(plan.segments[0].height_m == options.height_m);
  REQUIRE(plan.walls.size() == 4);
  int side = 0, caps = 0;
  for (const Wall& w : plan.walls) {
    CHECK(w.segment_id == plan.segments[0].id);
    if (w.side_wall) {
      ++side;
      CHECK(w.length() == Approx(55.0).margin(kPlanTolM));
      CHECK(std::abs(w.start.y()) == Approx(1.2).margin(kPlanTolM));
      // Side walls face the axis: -y on the left wall, +y on the right one.
      CHECK(w.inward_normal.y() == Approx(w.start.y() > 0 ? -1.0 : 1.0).margin(kPlanTolM));
    } else {
      ++caps;
      CHECK(w.length() == Approx(2.4).margin(kPlanTolM));
      CHECK(w.inward_normal.x() == Approx(w.start.x() < 1 ? 1.0 : -1.0).margin(kPlanTolM));
    }
  }
  CHECK(side == 2);
  CHECK(caps == 2);
  CheckPlanInvariants(options, plan, 55.0 * 2.4);
  // 16 doors on two equal walls: 8 each.
  for (std::size_t k = 0; k < plan.walls.size(); ++k) {
    CHECK(plan.doors_per_wall[k] == (plan.walls[k].side_wall ? 8 : 0));
  }
}

TEST_CASE("an L-turn has two segments and six walls", "[worlds][layout]") {
  const WorldOptions options = OptionsOf(Layout::kLTurn, 30, 20, 14);
  const LayoutPlan plan = Plan(options);
  REQUIRE(plan.segments.size() == 2);
  CHECK(plan.segments[0].end.isApprox(plan.segments[1].start));
  CHECK(plan.segments[1].end.isApprox(Vector2d(30, 20)));  // the second leg turns left (+y)
  CHECK(plan.walls.size() == 6);
  CHECK(SideWalls(plan) == 4);
  CheckPlanInvariants(options, plan, (30.0 + 20.0) * 2.4);
}

TEST_CASE("a T-junction has two segments and eight walls", "[worlds][layout]") {
  const WorldOptions options = OptionsOf(Layout::kTJunction, 40, 15, 14);
  const LayoutPlan plan = Plan(options);
  REQUIRE(plan.segments.size() == 2);
  CHECK(plan.segments[1].start.isApprox(Vector2d(20, 0)));  // the branch leaves from the middle
  CHECK(plan.segments[1].end.isApprox(Vector2d(20, 15)));
  CHECK(plan.walls.size() == 8);
  // Main corridor plus the branch, minus the half width the branch shares with it.
  CheckPlanInvariants(options, plan, 40.0 * 2.4 + 15.0 * 2.4 - 2.4 * 1.2);
}

TEST_CASE("a loop has four segments, four outer and four inner walls", "[worlds][layout]") {
  const WorldOptions options = OptionsOf(Layout::kLoop, 30, 16, 20);
  const LayoutPlan plan = Plan(options);
  REQUIRE(plan.segments.size() == 4);
  CHECK(plan.segments[3].end.isApprox(plan.segments[0].start));  // closed
  REQUIRE(plan.walls.size() == 8);
  // Outer walls face the inside of the block (towards its centre), inner walls face away from it.
  const Vector2d centre(15, 8);
  int outer = 0, inner = 0;
  for (const Wall& w : plan.walls) {
    const Vector2d mid = (w.start + w.end) / 2;
    const bool faces_centre = (centre - mid).dot(w.inward_normal) > 0;
    const bool is_outer =
        std::abs(mid.x() - centre.x()) > 15.5 || std::abs(mid.y() - centre.y()) > 8.5;
    CHECK(faces_centre == is_outer);
    (is_outer ? outer : inner)++;
    CHECK(w.side_wall);  // every wall of a loop runs along a segment
  }
  CHECK(outer == 4);
  CHECK(inner == 4);
  CheckPlanInvariants(options, plan, 2 * (30.0 + 16.0) * 2.4);
}

TEST_CASE("plan ids run from first_id: segments first, then walls", "[worlds][layout]") {
  const LayoutPlan plan = Plan(OptionsOf(Layout::kLoop, 30, 16, 20), 100);
  int expected = 100;
  for (const CorridorSegment& s : plan.segments) CHECK(s.id == expected++);
  for (const Wall& w : plan.walls) CHECK(w.id == expected++);
}

TEST_CASE("doors are shared between side walls by their usable length", "[worlds][layout]") {
  // L-turn 30 + 20: the long legs' walls get more doors than the short ones.
  const WorldOptions options = OptionsOf(Layout::kLTurn, 30, 20, 14);
  const LayoutPlan plan = Plan(options);
  for (std::size_t i = 0; i < plan.walls.size(); ++i) {
    for (std::size_t j = 0; j < plan.walls.size(); ++j) {
      if (!plan.walls[i].side_wall || !plan.walls[j].side_wall) continue;
      if (plan.walls[i].length() > plan.walls[j].length() + 1.0) {
        CHECK(plan.doors_per_wall[i] >= plan.doors_per_wall[j]);
      }
    }
  }
}

TEST_CASE("zero doors leave every wall without a doorway", "[worlds][layout]") {
  const WorldOptions options = OptionsOf(Layout::kTJunction, 40, 15, 0);
  const LayoutPlan plan = Plan(options);
  for (const int n : plan.doors_per_wall) CHECK(n == 0);
}

TEST_CASE("more doors than the side walls hold are a problem with doors.count",
          "[worlds][layout]") {
  WorldOptions options;
  options.doors.count = 200;
  const OptionsProblem problem = PlanProblem(options);
  CHECK(problem.key == "doors.count");
  CHECK(test::Contains(problem.message, "200 doorways do not fit"));
  // 55 m walls, 52.6 m usable, 1.06 m doors with 1.2 m gaps: 23 per wall.
  CHECK(test::Contains(problem.message, "at most 46 fit"));
}

TEST_CASE("exactly as many doors as fit are accepted", "[worlds][layout]") {
  WorldOptions options;
  options.doors.count = 46;
  CheckPlanInvariants(options, Plan(options), 55.0 * 2.4);
  options.doors.count = 47;
  CHECK(PlanProblem(options).key == "doors.count");
}

TEST_CASE("a door wider than every wall is a problem with doors.width_m", "[worlds][layout]") {
  WorldOptions options;
  options.doors.width_m = 60;
  const OptionsProblem problem = PlanProblem(options);
  CHECK(problem.key == "doors.width_m");
  CHECK(test::Contains(problem.message, "wider than every wall segment"));
}

TEST_CASE("usable wall length keeps min_gap_m free at both ends", "[worlds][layout]") {
  WorldOptions options;
  Wall wall;
  wall.start = Vector2d(0, 0);
  wall.end = Vector2d(10, 0);
  CHECK(UsableWallLength(wall, options) == Approx(10 - 2 * options.doors.min_gap_m));
  wall.end = Vector2d(2, 0);
  CHECK(UsableWallLength(wall, options) == 0.0);
}

}  // namespace
}  // namespace corridorsim::worlds
