// Tests worlds::Generate (worlds/generator*.cpp): invariants of generated worlds for every layout
// and several seeds (doors, plates, lamps, rooms, corner points, distractors, ids, meshes, a
// drivable centre line), the error for distractors that do not fit and lamps at a corridor's far
// end. Determinism and independent random streams: generator_determinism_test.cpp.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/expect_input_error.h"
#include "tests/support/generator_layouts.h"
#include "tests/support/tolerances.h"
#include "worlds/layout.h"
#include "worlds/world.h"

namespace corridorsim::worlds {
namespace {

using Eigen::AlignedBox2d;
using Eigen::AlignedBox3d;
using Eigen::Vector2d;
using Eigen::Vector3d;

using test::InsideAny;
using test::kFloatTol;
using test::kGeomTolM;
using test::LayoutOptions;

// The generator's fixed offsets (worlds/generator_internal.h), as the ground truth documents them.
constexpr double kLampDropM = 0.005;       // lamps hang this far below the ceiling
constexpr double kPlateMaxOffsetM = 0.01;  // a plate's front face stands this close to its wall

// ---- the worlds under test -------------------------------------------------------------------

struct GeneratedCase {
  std::string name;  // layout and seed, for failure messages
  WorldOptions options;
  std::uint64_t seed = 0;
  World world;
  LayoutPlan plan;  // the floor plan the world was built on
  std::map<std::string, const Mesh*> mesh_by_name;
};

// Every layout with seeds 1..5, generated once per test process.
const std::vector<GeneratedCase>& Cases() {
  static const std::vector<GeneratedCase> cases = [] {
    std::vector<GeneratedCase> out;
    for (const WorldOptions& options : LayoutOptions()) {
      for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        GeneratedCase c;
        c.name = LayoutName(options.layout) + " seed " + std::to_string(seed);
        c.options = options;
        c.seed = seed;
        c.world = Generate(options, seed);
        REQUIRE_FALSE(PlanLayout(options, 1, &c.plan));
        out.push_back(std::move(c));
      }
    }
    for (GeneratedCase& c : out) {
      for (const Mesh& m : c.world.meshes) c.mesh_by_name[m.name] = &m;
    }
    return out;
  }();
  return cases;
}

// Calls `check(c, c.world)` for every case c, naming the case in failure messages.
template <class Check>
void ForEachCase(Check&& check) {
  for (const GeneratedCase& c : Cases()) {
    INFO(c.name);
    check(c, c.world);
  }
}

// ---- wall geometry ---------------------------------------------------------------------------

struct Span {
  double lo, hi;  // along a wall, from its start (m)
};

bool SpansOverlap(const Span& a, const Span& b) {
  return a.lo < b.hi - kGeomTolM && b.lo < a.hi - kGeomTolM;
}

double Along(const Wall& w, const Vector2d& p) { return (p - w.start).dot(w.tangent()); }
double Across(const Wall& w, const Vector2d& p) { return (p - w.start).dot(w.inward_normal); }

const Wall& WallOf(const World& world, int wall_id) {
  const auto it = std::find_if(world.walls.begin(), world.walls.end(),
                               [&](const Wall& w) { return w.id == wall_id; });
  REQUIRE(it != world.walls.end());
  return *it;
}

const Doorway& DoorOf(const World& world, int door_id) {
  const auto it = std::find_if(world.doors.begin(), world.doors.end(),
                               [&](const Doorway& d) { return d.id == door_id; });
  REQUIRE(it != world.doors.end());
  return *it;
}

// A doorway's footprint along its wall: both columns included.
Span DoorSpan(const World& world, const Doorway& d) {
  const Wall& w = WallOf(world, d.wall_id);
  return {Along(w, d.column_a) - d.column_width_m / 2, Along(w, d.column_b) + d.column_width_m / 2};
}

Span PlateSpan(const World& world, const DoorPlate& p) {
  const Wall& w = WallOf(world, DoorOf(world, p.door_id).wall_id);
  const double c = Along(w, p.center.head<2>());
  return {c - p.size_m.x() / 2, c + p.size_m.x() / 2};
}

Span CentredSpan(const Wall& w, const Vector3d& center, double length) {
  const double c = Along(w, center.head<2>());
  return {c - length / 2, c + length / 2};
}

// Everything standing on a wall face, for overlap checks: what it is and where.
struct WallItem {
  std::string what;
  Span span;
};

std::map<int, std::vector<WallItem>> WallItems(const World& world) {
  std::map<int, std::vector<WallItem>> items;
  for (const Doorway& d : world.doors) {
    items[d.wall_id].push_back({"door " + std::to_string(d.id), DoorSpan(world, d)});
  }
  for (const DoorPlate& p : world.plates) {
    items[DoorOf(world, p.door_id).wall_id].push_back(
        {"plate " + std::to_string(p.id), PlateSpan(world, p)});
  }
  for (const Reflector& r : world.reflectors) {
    items[r.wall_id].push_back({"reflector " + std::to_string(r.id),
                                CentredSpan(WallOf(world, r.wall_id), r.center, r.size_m.x())});
  }
  for (const Distractor& d : world.distractors) {
    items[d.wall_id].push_back({"distractor " + std::to_string(d.id),
                                CentredSpan(WallOf(world, d.wall_id), d.center, d.size_m.x())});
  }
  return items;
}

// Interiors intersect (touching faces do not count).
bool Overlap(const AlignedBox2d& a, const AlignedBox2d& b) {
  return (a.min().array() < b.max().array() - 1e-6).all() &&
         (b.min().array() < a.max().array() - 1e-6).all();
}

AlignedBox2d Inflated(AlignedBox2d box, double by) {
  box.min().array() -= by;
  box.max().array() += by;
  return box;
}

bool HasMesh(const World& world, int instance_id, SemanticClass cls) {
  return std::any_of(world.meshes.begin(), world.meshes.end(), [&](const Mesh& m) {
    return m.instance_id == instance_id && m.semantic_class == cls;
  });
}

// ---- doorways --------------------------------------------------------------------------------

TEST_CASE("doorways on one wall keep min_gap_m between them and from the wall ends",
          "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase& c, const World& w) {
    REQUIRE(static_cast<int>(w.doors.size()) == c.options.doors.count);
    std::map<int, std::vector<Span>> spans;
    for (const Doorway& d : w.doors) spans[d.wall_id].push_back(DoorSpan(w, d));
    for (auto& [wall_id, list] : spans) {
      INFO("wall " << wall_id);
      const Wall& wall = WallOf(w, wall_id);
      std::sort(list.begin(), list.end(), [](const Span& a, const Span& b) { return a.lo < b.lo; });
      CHECK(list.front().lo >= c.options.doors.min_gap_m - kGeomTolM);
      CHECK(list.back().hi <= wall.length() - c.options.doors.min_gap_m + kGeomTolM);
      for (std::size_t i = 1; i < list.size(); ++i) {
        INFO("doorway spans [" << list[i - 1].lo << ", " << list[i - 1].hi << "] and ["
                               << list[i].lo << ", " << list[i].hi << "]");
        CHECK(list[i].lo - list[i - 1].hi >= c.options.doors.min_gap_m - kGeomTolM);
      }
    }
  });
}

TEST_CASE("every doorway has two columns on a side wall face and a frame of meshes",
          "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase& c, const World& w) {
    const DoorOptions& options = c.options.doors;
    for (const Doorway& d : w.doors) {
      INFO("door " << d.id);
      const Wall& wall = WallOf(w, d.wall_id);
      CHECK(wall.side_wall);
      CHECK(std::abs(Across(wall, d.column_a)) < kGeomTolM);
      CHECK(std::abs(Across(wall, d.column_b)) < kGeomTolM);
      CHECK(Along(wall, d.column_a) > 0);
      CHECK(Along(wall, d.column_b) < wall.length());
      CHECK((d.column_b - d.column_a).dot(wall.tangent()) > 0);  // b follows a along the wall
      CHECK((d.column_b - d.column_a).norm() ==
            Approx(d.width_m + d.column_width_m).margin(kGeomTolM));
      CHECK((d.inward_normal - wall.inward_normal).norm() < kGeomTolM);
      CHECK(d.width_m == options.width_m);
      CHECK(d.column_width_m == options.frame_width_m);
      CHECK(d.top_height_m == options.height_m);

      const double bar_top = options.height_m + options.bar_height_m;
      for (const char* part : {"door_column_a_", "door_column_b_", "door_bar_"}) {
        const std::string name = part + std::to_string(d.id);
        INFO(name);
        const auto it = c.mesh_by_name.find(name);
        REQUIRE(it != c.mesh_by_name.end());
        const Mesh& m = *it->second;
        CHECK(m.semantic_class == SemanticClass::kDoorFrame);
        CHECK(m.instance_id == d.id);
        CHECK(m.bounds.max().z() == Approx(bar_top).margin(kFloatTol));
        if (std::string(part) == "door_bar_") {
          CHECK(m.bounds.min().z() == Approx(options.height_m).margin(kFloatTol));
        } else {
          // Columns stand on the floor and run a little below it (no seam onto the void).
          CHECK(m.bounds.min().z() <= 0.0f);
          CHECK(m.bounds.min().z() >= -0.1f);
        }
      }
      // Each column mesh stands on its column point.
      for (const auto& [name, point] :
           {std::pair{"door_column_a_", d.column_a}, std::pair{"door_column_b_", d.column_b}}) {
        const Mesh& m = *c.mesh_by_name.at(name + std::to_string(d.id));
        const Vector2d centre = m.bounds.center().head<2>().cast<double>();
        CHECK(std::abs(Along(wall, centre) - Along(wall, point)) < kFloatTol * 100);
      }

      // Closed doors have a leaf and no room; open ones a leaf and a room; empty ones only a room.
      const bool has_leaf = c.mesh_by_name.count("door_leaf_" + std::to_string(d.id)) > 0;
      CHECK(has_leaf == (d.state != DoorState::kEmpty));
      if (d.state == DoorState::kClosed) CHECK_FALSE(d.room);
    }
  });
}

TEST_CASE("room numbers are unique across doors", "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase&, const World& w) {
    std::set<std::string> numbers;
    for (const Doorway& d : w.doors) {
      CHECK_FALSE(d.room_number.empty());
      CHECK(numbers.insert(d.room_number).second);
    }
  });
}

// ---- door plates -----------------------------------------------------------------------------

TEST_CASE("each door plate is on its door's wall, beside the frame, at the options height",
          "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase& c, const World& w) {
    const PlateOptions& options = c.options.plates;
    CHECK(static_cast<int>(w.plates.size()) == options.count);
    std::set<std::string> numbers;
    std::set<int> doors_with_plates;
    for (const DoorPlate& p : w.plates) {
      INFO("plate " << p.id << " of door " << p.door_id);
      const Doorway& door = DoorOf(w, p.door_id);
      const Wall& wall = WallOf(w, door.wall_id);
      CHECK(doors_with_plates.insert(p.door_id).second);  // one plate per door
      CHECK(p.room_number == door.room_number);
      CHECK(numbers.insert(p.room_number).second);

      // On the wall plane (just in front of it), facing into the corridor.
      const double offset = Across(wall, p.center.head<2>());
      CHECK(offset > 0);
      CHECK(offset < kPlateMaxOffsetM);
      CHECK((p.normal - Vector3d(wall.inward_normal.x(), wall.inward_normal.y(), 0)).norm() <
            kGeomTolM);
      CHECK(p.center.z() == Approx(options.center_height_m).margin(kGeomTolM));

      // Size within the jitter, aspect ratio kept.
      CHECK(p.size_m.x() >= options.width_m * (1 - options.size_jitter) - kGeomTolM);
      CHECK(p.size_m.x() <= options.width_m * (1 + options.size_jitter) + kGeomTolM);
      CHECK(p.size_m.x() / p.size_m.y() ==
            Approx(options.width_m / options.height_m).margin(kGeomTolM));

      // Beside the door: gap_from_frame_m from the nearer column's outer edge, inside the wall.
      const Span door_span = DoorSpan(w, door), plate = PlateSpan(w, p);
      const double gap =
          plate.hi <= door_span.lo ? door_span.lo - plate.hi : plate.lo - door_span.hi;
      INFO("plate [" << plate.lo << ", " << plate.hi << "], door [" << door_span.lo << ", "
                     << door_span.hi << "]");
      CHECK(gap == Approx(options.gap_from_frame_m).margin(kGeomTolM));
      CHECK(plate.lo > 0);
      CHECK(plate.hi < wall.length());

      // Drawn: a mesh with the plate's id and a texture of its own.
      CHECK(HasMesh(w, p.id, SemanticClass::kDoorPlate));
      REQUIRE(p.texture >= 0);
      REQUIRE(p.texture < static_cast<int>(w.textures.size()));
      const Texture& tex = w.textures[p.texture];
      CHECK(tex.name == "plate_" + std::to_string(p.id));
      CHECK_FALSE(tex.image.empty());
      CHECK(tex.image.data.size() ==
            static_cast<std::size_t>(tex.image.width) * tex.image.height * tex.image.channels);
      CHECK(p.font.rfind("hershey_", 0) == 0);  // the seeded style is recorded
    }
  });
}

TEST_CASE("plate styles vary with the seed: several fonts and designs appear",
          "[worlds][generator]") {
  std::set<std::string> fonts;
  std::set<int> borders;
  for (const GeneratedCase& c : Cases()) {
    for (const DoorPlate& p : c.world.plates) {
      fonts.insert(p.font);
      borders.insert(p.border_px);
    }
  }
  CHECK(fonts.size() >= 3);
  CHECK(borders.size() >= 2);
}

// ---- lamps and reflectors ---------------------------------------------------------------------

TEST_CASE("corridor lamps hang from the ceiling inside the corridor; room lamps in their room",
          "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase& c, const World& w) {
    const LampOptions& options = c.options.lamps;
    int corridor_lamps = 0;
    std::map<int, int> lamps_per_room;
    for (const Lamp& lamp : w.lamps) {
      INFO("lamp " << lamp.id << " at " << lamp.center.transpose());
      const Vector2d xy = lamp.center.head<2>();
      const SemanticClass cls = lamp.shape == LampShape::kCircular ? SemanticClass::kLampCircular
                                                                   : SemanticClass::kLampPanel;
      CHECK(HasMesh(w, lamp.id, cls));
      if (lamp.shape == LampShape::kCircular) {
        CHECK(lamp.radius_m >= options.radius_min_m);
        CHECK(lamp.radius_m <= options.radius_max_m);
      }
      if (lamp.room_door_id < 0) {
        ++corridor_lamps;
        CHECK(lamp.center.z() == Approx(c.options.height_m - kLampDropM).margin(kGeomTolM));
        // The whole emitting face lies in the walkable area of one segment.
        const Vector2d half = lamp.shape == LampShape::kCircular
                                  ? Vector2d(lamp.radius_m, lamp.radius_m)
                                  : Vector2d(lamp.size_m / 2);
        if (lamp.shape == LampShape::kPanel) {
          CHECK(lamp.size_m.maxCoeff() == options.panel_length_m);
          CHECK(lamp.size_m.minCoeff() == options.panel_width_m);
        }
        CHECK(InsideAny(c.plan.segment_rects, AlignedBox2d(xy - half, xy + half)));
      } else {
        const Doorway& door = DoorOf(w, lamp.room_door_id);
        REQUIRE(door.room);
        ++lamps_per_room[door.id];
        CHECK(lamp.shape == LampShape::kCircular);
        CHECK(door.room->footprint.contains(xy));
        CHECK(lamp.center.z() ==
              Approx(door.room->ceiling_height_m - kLampDropM).margin(kGeomTolM));
      }
    }
    CHECK(corridor_lamps > 0);
    // Every room has its ceiling lamp.
    for (const Doorway& d : w.doors) {
      if (d.room) CHECK(lamps_per_room[d.id] == (options.room_lamps ? 1 : 0));
    }
  });
}

TEST_CASE("reflectors mirror a lit circular lamp in their wall's plane", "[worlds][generator]") {
  int reflectors = 0;
  ForEachCase([&](const GeneratedCase&, const World& w) {
    for (const Reflector& r : w.reflectors) {
      ++reflectors;
      INFO("reflector " << r.id);
      const Wall& wall = WallOf(w, r.wall_id);
      CHECK(wall.side_wall);
      const auto lamp = std::find_if(w.lamps.begin(), w.lamps.end(),
                                     [&](const Lamp& l) { return l.id == r.mirrored_lamp_id; });
      REQUIRE(lamp != w.lamps.end());
      CHECK(lamp->shape == LampShape::kCircular);
      CHECK(lamp->on);
      CHECK(std::abs(Across(wall, r.center.head<2>())) < kGeomTolM);
      CHECK(Across(wall, r.apparent_lamp_center.head<2>()) ==
            Approx(-Across(wall, lamp->center.head<2>())).margin(kGeomTolM));
      CHECK(Along(wall, r.apparent_lamp_center.head<2>()) ==
            Approx(Along(wall, lamp->center.head<2>())).margin(kGeomTolM));
      CHECK(r.apparent_lamp_center.z() == lamp->center.z());
      CHECK(HasMesh(w, r.id, SemanticClass::kReflector));
    }
  });
  CHECK(reflectors > 0);  // the default reflector_fraction places some over 20 worlds
}

// ---- rooms -----------------------------------------------------------------------------------

TEST_CASE("rooms behind doorways overlap neither each other, the corridor nor a mirror",
          "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase& c, const World& w) {
    const double t = c.options.wall_thickness_m;
    std::vector<std::pair<int, AlignedBox2d>> rooms;  // door id, footprint with its walls
    for (const Doorway& d : w.doors) {
      if (!d.room) continue;
      const Wall& wall = WallOf(w, d.wall_id);
      // Behind the doorway's wall, at the options's size.
      CHECK(Across(wall, d.room->footprint.center()) < -t);
      CHECK(d.room->ceiling_height_m == c.options.doors.room_height_m);
      rooms.emplace_back(d.id, Inflated(d.room->footprint, t));
    }
    for (std::size_t i = 0; i < rooms.size(); ++i) {
      INFO("room of door " << rooms[i].first);
      for (std::size_t j = i + 1; j < rooms.size(); ++j) {
        INFO("and room of door " << rooms[j].first);
        CHECK_FALSE(Overlap(rooms[i].second, rooms[j].second));
      }
      for (const AlignedBox2d& corridor : c.plan.segment_rects)
        CHECK_FALSE(Overlap(rooms[i].second, corridor));
      for (const Reflector& r : w.reflectors) {
        // The mirrored corridor behind a reflective panel: the panel's length, a width deep.
        const Wall& wall = WallOf(w, r.wall_id);
        const Span s = CentredSpan(wall, r.center, r.size_m.x());
        AlignedBox2d mirror(wall.start + (s.lo - t) * wall.tangent());
        mirror.extend(wall.start + (s.hi + t) * wall.tangent() -
                      (c.options.width_m + t) * wall.inward_normal);
        INFO("reflector " << r.id);
        CHECK_FALSE(Overlap(rooms[i].second, mirror));
      }
    }
  });
}

// ---- ceiling corner points ---------------------------------------------------------------------

TEST_CASE("ceiling corner points lie on the ceiling inside the corridor; vents give four each",
          "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase& c, const World& w) {
    const double H = c.options.height_m;
    std::map<CornerKind, int> counts;
    std::vector<Vector3d> vent_corners;
    for (const CornerPoint& p : w.corner_points) {
      INFO(CornerKindName(p.kind) << " " << p.id << " at " << p.position.transpose());
      ++counts[p.kind];
      CHECK(InsideAny(c.plan.floor_cells, Vector2d(p.position.head<2>())));
      CHECK(p.position.z() <= H);
      CHECK(p.position.z() > H - 0.05);
      if (p.kind == CornerKind::kTileSeam) CHECK(p.position.z() == H);
      if (p.kind == CornerKind::kVent) vent_corners.push_back(p.position);
    }
    CHECK(counts[CornerKind::kTileSeam] > 0);
    REQUIRE(vent_corners.size() % 4 == 0);
    // Each vent's four corners are a square of vent_size_m in one horizontal plane.
    const double size = c.options.ceiling.vent_size_m;
    for (std::size_t i = 0; i < vent_corners.size(); i += 4) {
      AlignedBox3d box(vent_corners[i]);
      for (std::size_t k = 1; k < 4; ++k) box.extend(vent_corners[i + k]);
      CHECK(box.sizes().x() == Approx(size).margin(kGeomTolM));
      CHECK(box.sizes().y() == Approx(size).margin(kGeomTolM));
      CHECK(box.sizes().z() == 0.0);
      std::set<std::pair<double, double>> distinct;
      for (std::size_t k = 0; k < 4; ++k)
        distinct.insert({vent_corners[i + k].x(), vent_corners[i + k].y()});
      CHECK(distinct.size() == 4);
    }
  });
}

// ---- distractors -----------------------------------------------------------------------------

TEST_CASE("distractors come in the classes and counts the options asks for, against side walls",
          "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase& c, const World& w) {
    const DistractorOptions& x = c.options.distractors;
    std::map<SemanticClass, int> counts;
    for (const Distractor& d : w.distractors) {
      INFO(SemanticClassName(d.semantic_class) << " " << d.id);
      ++counts[d.semantic_class];
      const Wall& wall = WallOf(w, d.wall_id);
      CHECK(wall.side_wall);
      CHECK((d.normal - Vector3d(wall.inward_normal.x(), wall.inward_normal.y(), 0)).norm() <
            kGeomTolM);
      // Its box stands on the wall face and reaches size.y into the corridor.
      CHECK(Across(wall, d.center.head<2>()) == Approx(d.size_m.y() / 2).margin(kGeomTolM));
      const Span s = CentredSpan(wall, d.center, d.size_m.x());
      CHECK(s.lo > 0);
      CHECK(s.hi < wall.length());
      CHECK(d.center.z() - d.size_m.z() / 2 >= -kGeomTolM);
      CHECK(d.center.z() + d.size_m.z() / 2 <= c.options.height_m);
      CHECK(HasMesh(w, d.id, d.semantic_class));
      const bool has_text = d.semantic_class == SemanticClass::kPoster ||
                            d.semantic_class == SemanticClass::kNoticeBoard;
      CHECK(d.text.empty() != has_text);
      if (has_text) CHECK(d.text.find_first_not_of("0123456789") == std::string::npos);
    }
    CHECK(counts[SemanticClass::kPoster] == x.posters);
    CHECK(counts[SemanticClass::kNoticeBoard] == x.notice_boards);
    CHECK(counts[SemanticClass::kBookshelf] == x.bookshelves);
    CHECK(counts[SemanticClass::kCabinet] == x.cabinets);
    CHECK(counts[SemanticClass::kFireExtinguisher] == x.fire_extinguishers);
    CHECK(counts.size() == 5);
  });
}

TEST_CASE("doorways, plates, reflectors and distractors never overlap along a wall",
          "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase&, const World& w) {
    for (const auto& [wall_id, items] : WallItems(w)) {
      for (std::size_t i = 0; i < items.size(); ++i) {
        for (std::size_t j = i + 1; j < items.size(); ++j) {
          INFO("wall " << wall_id << ": " << items[i].what << " [" << items[i].span.lo << ", "
                       << items[i].span.hi << "] and " << items[j].what << " [" << items[j].span.lo
                       << ", " << items[j].span.hi << "]");
          CHECK_FALSE(SpansOverlap(items[i].span, items[j].span));
        }
      }
    }
  });
}

// ---- ids, meshes, collision boxes
// ----------------------------------------------------------------

TEST_CASE("ids are unique across every kind of ground truth entry", "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase& c, const World& w) {
    std::map<int, std::string> owner;
    auto add = [&](int id, const std::string& what) {
      const auto [it, inserted] = owner.emplace(id, what);
      INFO(what << " has id " << id << ", already used by " << it->second);
      CHECK(id > 0);
      CHECK(inserted);
    };
    for (const auto& x : w.segments) add(x.id, "segment");
    for (const auto& x : w.walls) add(x.id, "wall");
    for (const auto& x : w.doors) add(x.id, "door");
    for (const auto& x : w.plates) add(x.id, "plate");
    for (const auto& x : w.lamps) add(x.id, "lamp");
    for (const auto& x : w.reflectors) add(x.id, "reflector");
    for (const auto& x : w.corner_points) add(x.id, "corner point");
    for (const auto& x : w.distractors) add(x.id, "distractor");
    // Mesh names are unique too (they name the OBJ groups).
    CHECK(c.mesh_by_name.size() == w.meshes.size());
  });
}

TEST_CASE("meshes have indices in range, unit normals and valid materials", "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase&, const World& w) {
    for (const Mesh& m : w.meshes) {
      INFO("mesh " << m.name);
      REQUIRE_FALSE(m.positions.empty());
      CHECK(m.normals.size() == m.positions.size());
      CHECK(m.uvs.size() == m.positions.size());
      CHECK(m.indices.size() % 3 == 0);
      CHECK(m.triangle_count() > 0);
      const std::uint32_t max_index = *std::max_element(m.indices.begin(), m.indices.end());
      CHECK(max_index < m.positions.size());
      int bad_normals = 0, outside_bounds = 0;
      for (const Eigen::Vector3f& n : m.normals)
        bad_normals += std::abs(n.norm() - 1.0f) > kFloatTol;
      for (const Eigen::Vector3f& p : m.positions) outside_bounds += !m.bounds.contains(p);
      CHECK(bad_normals == 0);
      CHECK(outside_bounds == 0);
      REQUIRE(m.material >= 0);
      REQUIRE(m.material < static_cast<int>(w.materials.size()));
      const int tex = w.materials[m.material].texture;
      CHECK(tex >= -1);
      CHECK(tex < static_cast<int>(w.textures.size()));
    }
  });
}

TEST_CASE("collision boxes have positive half extents", "[worlds][generator]") {
  ForEachCase([&](const GeneratedCase&, const World& w) {
    for (const CollisionBox& b : w.collision_boxes) {
      INFO(SemanticClassName(b.semantic_class)
           << " " << b.instance_id << " at " << b.center.transpose());
      CHECK((b.half_extents.array() > 0).all());
    }
  });
}

TEST_CASE("the robot can drive along every corridor centre line", "[worlds][generator]") {
  constexpr double kHalfWidthM = 0.3, kZLowM = 0.05, kZHighM = 0.5;
  ForEachCase([&](const GeneratedCase&, const World& w) {
    // The ground slab: floor class, top at z = 0.
    const auto ground = std::find_if(
        w.collision_boxes.begin(), w.collision_boxes.end(),
        [](const CollisionBox& b) { return b.semantic_class == SemanticClass::kFloor; });
    REQUIRE(ground != w.collision_boxes.end());
    CHECK(ground->center.z() + ground->half_extents.z() == Approx(0.0).margin(kGeomTolM));
    for (const CorridorSegment& seg : w.segments) {
      const Vector2d side(-seg.direction().y(), seg.direction().x());
      AlignedBox3d lane;
      lane.setEmpty();
      for (const Vector2d& p : {seg.start, seg.end}) {
        for (const double s : {-kHalfWidthM, kHalfWidthM}) {
          const Vector2d q = p + s * side;
          lane.extend(Vector3d(q.x(), q.y(), kZLowM));
          lane.extend(Vector3d(q.x(), q.y(), kZHighM));
        }
      }
      for (const CollisionBox& b : w.collision_boxes) {
        const AlignedBox3d box(b.center - b.half_extents, b.center + b.half_extents);
        const bool blocks = (box.min().array() < lane.max().array() - kGeomTolM).all() &&
                            (lane.min().array() < box.max().array() - kGeomTolM).all();
        INFO("segment " << seg.id << " blocked by " << SemanticClassName(b.semantic_class) << " "
                        << b.instance_id << " from " << box.min().transpose() << " to "
                        << box.max().transpose());
        CHECK_FALSE(blocks);
      }
    }
  });
}

// ---- all_options the generator cannot place
// ----------------------------------------------------------

TEST_CASE("more distractors than fit on the walls throw a OptionsError naming the kind",
          "[worlds][generator]") {
  struct Case {
    const char* key;
    int DistractorOptions::*field;
  };
  for (const Case& k :
       {Case{"distractors.posters", &DistractorOptions::posters},
        Case{"distractors.bookshelves", &DistractorOptions::bookshelves},
        Case{"distractors.fire_extinguishers", &DistractorOptions::fire_extinguishers}}) {
    INFO(k.key);
    WorldOptions options;
    options.distractors.*k.field = 300;
    REQUIRE_FALSE(options.Check());  // the options is valid; only the generated walls are too short
    const OptionsProblem p = test::OptionsErrorOf([&] { Generate(options, 1); });
    CHECK(p.key == k.key);
    CHECK(test::Contains(p.message, " of 300 fit on the free wall stretches"));
  }
}

TEST_CASE("Generate rejects a options that fails Check with its problem", "[worlds][generator]") {
  WorldOptions options;
  options.plates.count = 20;
  const OptionsProblem p = test::OptionsErrorOf([&] { Generate(options, 1); });
  CHECK(p.key == "plates.count");
}

TEST_CASE("lamps near the far end of a corridor stay inside it", "[worlds][generator]") {
  // The last lamp slot of a 40.6 m corridor with 3 m spacing is at 40.5 m, 0.1 m before the end
  // wall; panel lamps reach 0.6 m along the axis from their centre.
  for (const Layout layout : {Layout::kStraight, Layout::kTJunction, Layout::kLTurn}) {
    WorldOptions options;
    options.layout = layout;
    options.length_m = 40.6;
    options.second_length_m = 16.6;
    options.lamps.circular_fraction = 0.0;
    LayoutPlan plan;
    REQUIRE_FALSE(PlanLayout(options, 1, &plan));
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      const World w = Generate(options, seed);
      for (const Lamp& lamp : w.lamps) {
        if (lamp.room_door_id >= 0) continue;
        const Vector2d xy = lamp.center.head<2>();
        INFO(LayoutName(layout) << " seed " << seed << ": lamp " << lamp.id << " at "
                                << xy.transpose() << " size " << lamp.size_m.transpose());
        CHECK(InsideAny(plan.segment_rects,
                        AlignedBox2d(xy - lamp.size_m / 2, xy + lamp.size_m / 2)));
      }
    }
  }
}

}  // namespace
}  // namespace corridorsim::worlds
