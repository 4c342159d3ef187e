#pragma once
// What the world generator's files share: the Builder that holds one world while it is made, its
// random streams and its bookkeeping (which wall stretches are taken, the ceiling's keepouts).
// worlds::Generate (generator.cpp) runs its steps in one fixed order (Builder::Build), each step
// in the file of its concern, so the random draws happen in that order whichever file holds them.
// Internal to worlds/.

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "common/random.h"
#include "worlds/layout.h"
#include "worlds/world.h"

namespace corridorsim::worlds::generator_internal {

using Eigen::AlignedBox2d;
using Eigen::AlignedBox3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::Vector3f;

inline constexpr double kWallPeriodM = 2.0;   // wall texture repeat
inline constexpr double kFloorPeriodM = 2.0;  // floor texture repeat (4 x 4 linoleum tiles)
inline constexpr int kCeilingTilesPerTexture = 4;
inline constexpr double kLampDrop = 0.005;  // lamps hang this far below the ceiling (no z-fighting)
inline constexpr double kSurfaceOffset =
    0.002;  // decals (plates, posters) in front of their backing
inline constexpr int kDiscSegments = 32;
// Solids that meet the floor or the ceiling run this far beyond it, so that the seam between
// two separate meshes is a crossing, not two edges touching: a ray through the seam then hits
// the wall's continuation instead of passing into the void behind.
inline constexpr double kSeam = 0.05;

struct Interval {
  double lo, hi;
};

inline bool Overlaps(const AlignedBox2d& a, const AlignedBox2d& b, double eps = 1e-6) {
  return a.min().x() < b.max().x() - eps && b.min().x() < a.max().x() - eps &&
         a.min().y() < b.max().y() - eps && b.min().y() < a.max().y() - eps;
}

inline AlignedBox2d Inflated(AlignedBox2d box, double by) {
  box.min().array() -= by;
  box.max().array() += by;
  return box;
}

inline std::string Id(const char* prefix, int id) {
  return std::string(prefix) + "_" + std::to_string(id);
}

class Builder {
 public:
  Builder(const WorldOptions& options, std::uint64_t seed);
  World Build();

 private:
  struct Slot {
    int wall;
    double s0;  // start along the wall
  };
  struct DistractorKind {
    const char* key;  // options key, for errors
    SemanticClass cls;
    int count;
  };

  // ---- generator.cpp: appearance, materials, textures, meshes, taken stretches, bounds ----------
  void DrawAppearance(RandomStream rng);
  int AddTexture(std::string name, Image8 image);
  int AddMaterial(Material m);
  int PlainMaterial(const std::string& name, Eigen::Vector3f diffuse, float specular = 0.0f);
  int TexturedMaterial(const std::string& name, int texture, Eigen::Vector3f tint = {1, 1, 1});
  Mesh& NewMesh(std::string name, int material, int instance_id, SemanticClass cls);
  void Collide(const AlignedBox3d& box, int instance_id, SemanticClass cls);
  void Solid(const std::string& name, int material, int id, SemanticClass cls,
             const AlignedBox3d& box, double uv_period = kWallPeriodM);
  void MakeBaseMaterials();
  bool IsFree(int wall, double lo, double hi) const;
  bool OverlapsRoomsOrCorridors(const AlignedBox2d& area) const;
  void AddDecal(const std::string& name, int material, int id, SemanticClass cls,
                const Vector3d& centre, const Vector3d& normal, double width, double height);
  void Finish();

  // ---- wall coordinates (every step places along walls) -----------------------------------------
  // A point on wall `w` at distance s along it, `offset` along its inward normal.
  static Vector2d OnWall(const Wall& w, double s, double offset) {
    return w.start + s * w.tangent() + offset * w.inward_normal;
  }
  static AlignedBox3d WallBox(const Wall& w, double s0, double s1, double z0, double z1,
                              double off0, double off1) {
    AlignedBox3d box;
    box.setEmpty();
    for (const double s : {s0, s1}) {
      for (const double off : {off0, off1}) {
        const Vector2d p = OnWall(w, s, off);
        box.extend(Vector3d(p.x(), p.y(), z0));
        box.extend(Vector3d(p.x(), p.y(), z1));
      }
    }
    return box;
  }
  static AlignedBox2d WallRect(const Wall& w, double s0, double s1, double off0, double off1) {
    AlignedBox2d box(OnWall(w, s0, off0));
    box.extend(OnWall(w, s1, off1));
    return box;
  }

  // ---- the keepout grid: calls visit({i, j}) for every kKeepoutCellM cell `box` touches ---------
  template <class Visit>
  static void ForKeepoutCells(const AlignedBox2d& box, Visit visit) {
    const auto cell = [](double v) { return static_cast<long>(std::floor(v / kKeepoutCellM)); };
    for (long i = cell(box.min().x()); i <= cell(box.max().x()); ++i) {
      for (long j = cell(box.min().y()); j <= cell(box.max().y()); ++j) visit({i, j});
    }
  }

  // ---- generator_shell.cpp: the corridor's walls, floor and ceiling -----------------------------
  bool OwnedByEarlierSegment(std::size_t k, const Vector2d& p, double margin) const;
  bool InsideCorridor(const AlignedBox2d& box, double margin) const;
  void BuildWalls();
  void BuildWallPiece(const Wall& wall, int k, double s0, double s1, int piece, double t, double H);
  void BuildFloorAndCeiling();
  std::vector<std::pair<AlignedBox2d, bool>> CeilingStretches(const AlignedBox2d& cell);
  bool OnPlainCeiling(const Vector2d& p, double margin) const;
  bool NearWall(const Vector2d& p, double margin) const;

  // ---- generator_doors.cpp: doorways and the rooms behind them ----------------------------------
  void PlaceDoors();
  void BuildDoor(std::size_t index);
  void BuildRoom(const Doorway& door, const Wall& wall);

  // ---- generator_plates.cpp: door plates --------------------------------------------------------
  static std::array<Vector3d, 2> PlateColours(RandomStream& rng);
  void PlacePlates();

  // ---- generator_lamps.cpp: lamps and the reflective panels mirroring them ----------------------
  int AddLamp(const Vector3d& centre, LampShape shape, double radius, const Vector2d& size,
              int room_door_id);  // a room's lamp too (BuildRoom, during PlaceDoors)
  void PlaceLamps();
  void PlaceReflectors();
  void BuildReflector(const Reflector& r, const Wall& wall, double s0, double s1, const Lamp& lamp);

  // ---- generator_ceiling.cpp: vents, sprinklers, smoke detectors, corner points -----------------
  bool CeilingFree(const AlignedBox2d& box) const;
  void AddCeilingKeepout(const AlignedBox2d& box);
  void AddCorner(CornerKind kind, const Vector3d& p);
  void PlaceCeilingFixtures();
  void AddRoundFixture(std::size_t k, const Vector2d& p, double r, double z, int material,
                       SemanticClass cls, CornerKind kind);
  void AddTileSeamCorners();

  // ---- generator_distractors.cpp: objects on the walls that detectors must reject ---------------
  std::optional<Slot> FindSlot(double width, double margin);
  void PlaceDistractors();
  void PlaceDistractor(const DistractorKind& kind, int n);

  struct Materials {
    int wall, room_wall, floor, room_floor, ceiling, room_ceiling, door_leaf, frame, vent, detector,
        sprinkler, mirror, extinguisher, furniture, metal, lamp_on, lamp_off;
  };

  const WorldOptions& s_;
  World w_;
  LayoutPlan plan_;
  int next_id_ = 1;  // 0 is "nothing" in label images
  RandomStream doors_rng_, plates_rng_, lamps_rng_, ceiling_rng_, distractors_rng_, textures_rng_;
  RandomStream plain_rng_;  // plain ceiling stretches: its own stream, so other draws keep theirs
  Materials mat_{};
  std::vector<std::vector<Interval>> occupied_;        // per wall: taken stretches
  std::vector<std::vector<Interval>> door_cuts_;       // per wall: door openings
  std::vector<std::vector<Interval>> reflector_cuts_;  // per wall: reflective panels
  std::vector<int> door_walls_;                        // per door: wall index
  std::vector<double> door_starts_;                    // per door: start along its wall
  std::vector<AlignedBox2d> room_areas_;               // rooms and mirror volumes, with walls
  std::vector<std::pair<int, int>> lamp_segment_;      // corridor lamps: (lamp id, segment index)
  std::vector<AlignedBox2d> ceiling_keepout_;          // lamps and fixtures on the ceiling
  // The keepouts by grid cell (kKeepoutCellM): a tile corner or fixture tests its neighbours
  // only, not every fixture of a kilometre of corridor.
  static constexpr double kKeepoutCellM = 2.0;
  std::map<std::pair<long, long>, std::vector<std::size_t>> keepout_cells_;
  Vector2d tile_offset_ = Vector2d::Zero();
  std::vector<AlignedBox2d> plain_ceiling_;  // corridor ceiling without tiles
  std::map<std::pair<long, long>, std::vector<std::size_t>> plain_cells_;  // by keepout grid cell
};

}  // namespace corridorsim::worlds::generator_internal
