// Tests worlds::Generate (worlds/generator*.cpp) for what the seed and the options change in a
// world and what they leave: determinism, independent random streams, plain ceiling stretches and
// plain walls that move nothing else. The invariants of every generated world are tested in
// generator_test.cpp.
#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/support/generator_layouts.h"
#include "worlds/world.h"
#include "worlds/world_io.h"

namespace corridorsim::worlds {
namespace {

using Eigen::AlignedBox2d;
using Eigen::Vector2d;
using test::InsideAny;
using test::LayoutOptions;

// ---- determinism and random streams
// --------------------------------------------------------------

// REQUIREs that `a` and `b` have the same size, then calls `check(a[i], b[i])` for each i.
template <class T, class Check>
void CheckEachPair(const std::vector<T>& a, const std::vector<T>& b, Check&& check) {
  REQUIRE(a.size() == b.size());
  for (std::size_t i = 0; i < a.size(); ++i) check(a[i], b[i]);
}

void CheckIdentical(const World& a, const World& b) {
  CHECK(GroundTruthJson(a).dump() == GroundTruthJson(b).dump());
  CheckEachPair(a.meshes, b.meshes, [](const Mesh& ma, const Mesh& mb) {
    INFO("mesh " << ma.name);
    CHECK(ma.name == mb.name);
    CHECK(ma.material == mb.material);
    CHECK(ma.instance_id == mb.instance_id);
    CHECK(ma.semantic_class == mb.semantic_class);
    CHECK(ma.positions == mb.positions);  // exact: same arithmetic on the same draws
    CHECK(ma.normals == mb.normals);
    CHECK(ma.uvs == mb.uvs);
    CHECK(ma.indices == mb.indices);
  });
  CheckEachPair(a.textures, b.textures, [](const Texture& ta, const Texture& tb) {
    INFO("texture " << ta.name);
    CHECK(ta.name == tb.name);
    CHECK(ta.image.width == tb.image.width);
    CHECK(ta.image.height == tb.image.height);
    CHECK(ta.image.data == tb.image.data);
  });
  CheckEachPair(a.materials, b.materials, [](const Material& ma, const Material& mb) {
    CHECK(ma.name == mb.name);
    CHECK(ma.texture == mb.texture);
    CHECK(ma.diffuse == mb.diffuse);
    CHECK(ma.emission == mb.emission);
  });
  CheckEachPair(a.collision_boxes, b.collision_boxes,
                [](const CollisionBox& ba, const CollisionBox& bb) {
                  CHECK(ba.center == bb.center);
                  CHECK(ba.half_extents == bb.half_extents);
                });
}

TEST_CASE("generating twice with the same options and seed gives identical worlds",
          "[worlds][generator][determinism]") {
  for (const WorldOptions& options : LayoutOptions()) {
    INFO(LayoutName(options.layout));
    CheckIdentical(Generate(options, 3), Generate(options, 3));
  }
}

std::vector<Vector2d> DoorColumns(const World& w) {
  std::vector<Vector2d> out;
  for (const Doorway& d : w.doors) {
    out.push_back(d.column_a);
    out.push_back(d.column_b);
  }
  return out;
}

TEST_CASE("another seed gives another layout of doors", "[worlds][generator][determinism]") {
  for (const WorldOptions& options : LayoutOptions()) {
    INFO(LayoutName(options.layout));
    const std::vector<Vector2d> a = DoorColumns(Generate(options, 1)),
                                b = DoorColumns(Generate(options, 2));
    REQUIRE(a.size() == b.size());
    double largest_move = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
      largest_move = std::max(largest_move, (a[i] - b[i]).norm());
    CHECK(largest_move > 0.01);
  }
}

TEST_CASE("changing the number of posters moves no door, plate or lamp",
          "[worlds][generator][determinism]") {
  for (const WorldOptions& base : LayoutOptions()) {
    INFO(LayoutName(base.layout));
    WorldOptions more = base;
    more.distractors.posters = base.distractors.posters + 3;
    WorldOptions none = base;
    none.distractors.posters = 0;
    const World reference = Generate(base, 4);
    for (const WorldOptions& changed : {more, none}) {
      INFO("posters " << changed.distractors.posters);
      const World other = Generate(changed, 4);
      CHECK(DoorColumns(other) == DoorColumns(reference));
      CheckEachPair(other.doors, reference.doors, [](const Doorway& da, const Doorway& db) {
        CHECK(da.state == db.state);
        CHECK(da.room_number == db.room_number);
      });
      CheckEachPair(other.plates, reference.plates, [](const DoorPlate& pa, const DoorPlate& pb) {
        CHECK(pa.center == pb.center);
        CHECK(pa.size_m == pb.size_m);
      });
      CheckEachPair(other.lamps, reference.lamps, [](const Lamp& la, const Lamp& lb) {
        CHECK(la.center == lb.center);
        CHECK(la.on == lb.on);
      });
      CHECK(static_cast<int>(other.distractors.size()) ==
            static_cast<int>(reference.distractors.size()) + changed.distractors.posters -
                base.distractors.posters);
    }
  }
}

TEST_CASE("plain ceiling stretches carry no tile corners and the rooms' plaster; tiles elsewhere",
          "[worlds][generator]") {
  for (const WorldOptions& base : LayoutOptions()) {
    INFO(LayoutName(base.layout));
    const World tiled = Generate(base, 3);
    WorldOptions half = base;
    half.ceiling.plain_fraction = 0.5;
    half.ceiling.plain_stretch_m = 3.0;
    WorldOptions all = base;
    all.ceiling.plain_fraction = 1.0;
    const auto material = [](const World& w, const Mesh& m) {
      return w.materials[m.material].name;
    };
    const auto count_tile_corners = [](const World& w) {
      return std::count_if(w.corner_points.begin(), w.corner_points.end(),
                           [](const CornerPoint& p) { return p.kind == CornerKind::kTileSeam; });
    };

    // All plain: no tile corner, every corridor ceiling mesh plastered; fixtures stay.
    const World plain = Generate(all, 3);
    CHECK(count_tile_corners(plain) == 0);
    CHECK(plain.corner_points.size() > 0);  // vents, sprinklers, smoke detectors
    for (const Mesh& m : plain.meshes) {
      if (m.semantic_class == SemanticClass::kCeiling) CHECK(material(plain, m) == "room_ceiling");
    }

    // Half: tile corners only under tiled meshes, each plain mesh free of them, and fewer of them.
    const World mixed = Generate(half, 3);
    std::vector<AlignedBox2d> plain_rects, tiled_rects;
    for (const Mesh& m : mixed.meshes) {
      if (m.semantic_class != SemanticClass::kCeiling) continue;
      const AlignedBox2d rect(m.bounds.min().head<2>().cast<double>(),
                              m.bounds.max().head<2>().cast<double>());
      (material(mixed, m) == "ceiling" ? tiled_rects : plain_rects).push_back(rect);
    }
    CHECK(!plain_rects.empty());
    CHECK(!tiled_rects.empty());
    for (const CornerPoint& p : mixed.corner_points) {
      if (p.kind != CornerKind::kTileSeam) continue;
      INFO("tile corner " << p.id << " at " << p.position.transpose());
      const Vector2d xy = p.position.head<2>();
      CHECK(InsideAny(tiled_rects, xy));
      for (const AlignedBox2d& r : plain_rects) CHECK_FALSE(r.contains(xy));
    }
    CHECK(count_tile_corners(mixed) < count_tile_corners(tiled));
    CHECK(count_tile_corners(mixed) > 0);

    // The stretches come from their own stream: doors, plates and lamps do not move.
    CHECK(DoorColumns(mixed) == DoorColumns(tiled));
    CheckEachPair(mixed.lamps, tiled.lamps,
                  [](const Lamp& a, const Lamp& b) { CHECK(a.center == b.center); });
  }
}

TEST_CASE("plain walls: the corridor's walls smooth, the rooms' speckled, the rest unchanged",
          "[worlds][generator]") {
  WorldOptions options;
  const World speckled = Generate(options, 4);
  options.wall_finish = WallFinish::kPlain;
  const World plain = Generate(options, 4);
  const auto texture_of = [](const World& w, const std::string& material) -> const Image8* {
    for (const Material& m : w.materials) {
      if (m.name == material) return m.texture >= 0 ? &w.textures[m.texture].image : nullptr;
    }
    return nullptr;
  };
  // Pixels with a step of more than 8 grey levels to their right or lower neighbour: speckles,
  // scuffs and seams, the corners' stuff; smooth paint has none.
  const auto steps = [](const Image8& image) {
    const auto grey = [&](int x, int y) {
      const std::size_t i = (static_cast<std::size_t>(y) * image.width + x) * image.channels;
      return (image.data[i] + image.data[i + 1] + image.data[i + 2]) / 3;
    };
    int count = 0;
    for (int y = 0; y + 1 < image.height; ++y) {
      for (int x = 0; x + 1 < image.width; ++x) {
        const int g = grey(x, y);
        count += std::abs(g - grey(x + 1, y)) > 8 || std::abs(g - grey(x, y + 1)) > 8;
      }
    }
    return count;
  };
  const Image8* corridor = texture_of(plain, "wall");
  const Image8* rooms = texture_of(plain, "room_wall");
  REQUIRE(corridor);
  REQUIRE(rooms);
  CHECK(steps(*corridor) == 0);
  CHECK(steps(*rooms) > 1000);
  CHECK(steps(*rooms) == steps(*texture_of(speckled, "wall")));  // the rooms keep their paint
  // Only the corridor walls' texture differs: the same meshes, doors, lamps and corner points.
  REQUIRE(plain.meshes.size() == speckled.meshes.size());
  for (std::size_t i = 0; i < plain.meshes.size(); ++i) {
    CHECK(plain.meshes[i].name == speckled.meshes[i].name);
  }
  CHECK(DoorColumns(plain) == DoorColumns(speckled));
  CHECK(plain.corner_points.size() == speckled.corner_points.size());
  CheckEachPair(plain.lamps, speckled.lamps,
                [](const Lamp& a, const Lamp& b) { CHECK(a.center == b.center); });
  REQUIRE(plain.textures.size() == speckled.textures.size() + 1);
  for (const Texture& t : speckled.textures) {
    INFO("texture " << t.name);
    const auto same = std::find_if(plain.textures.begin(), plain.textures.end(),
                                   [&](const Texture& p) { return p.name == t.name; });
    REQUIRE(same != plain.textures.end());
    CHECK((same->image.data == t.image.data));
  }
}

}  // namespace
}  // namespace corridorsim::worlds
