// worlds::Generate: WorldOptions + seed -> World. Each concern draws from its own random stream
// (worlds.doors, worlds.plates, ...), so changing one option does not reshuffle the others.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <string>

#include "common/random.h"
#include "worlds/layout.h"
#include "worlds/mesh_builder.h"
#include "worlds/textures.h"
#include "worlds/world.h"

namespace corridorsim::worlds {
namespace {

using Eigen::AlignedBox2d;
using Eigen::AlignedBox3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::Vector3f;

constexpr double kWallPeriodM = 2.0;   // wall texture repeat
constexpr double kFloorPeriodM = 2.0;  // floor texture repeat (4 x 4 linoleum tiles)
constexpr int kCeilingTilesPerTexture = 4;
constexpr double kLampDrop = 0.005;       // lamps hang this far below the ceiling (no z-fighting)
constexpr double kSurfaceOffset = 0.002;  // decals (plates, posters) in front of their backing
constexpr int kDiscSegments = 32;
// Solids that meet the floor or the ceiling run this far beyond it, so that the seam between
// two separate meshes is a crossing, not two edges touching: a ray through the seam then hits
// the wall's continuation instead of passing into the void behind.
constexpr double kSeam = 0.05;

struct Interval {
  double lo, hi;
};

bool Overlaps(const AlignedBox2d& a, const AlignedBox2d& b, double eps = 1e-6) {
  return a.min().x() < b.max().x() - eps && b.min().x() < a.max().x() - eps &&
         a.min().y() < b.max().y() - eps && b.min().y() < a.max().y() - eps;
}

AlignedBox2d Inflated(AlignedBox2d box, double by) {
  box.min().array() -= by;
  box.max().array() += by;
  return box;
}

std::string Id(const char* prefix, int id) {
  return std::string(prefix) + "_" + std::to_string(id);
}

class Builder {
 public:
  Builder(const WorldOptions& options, std::uint64_t seed)
      : s_(options),
        doors_rng_(seed, 0, "worlds.doors"),
        plates_rng_(seed, 0, "worlds.plates"),
        lamps_rng_(seed, 0, "worlds.lamps"),
        ceiling_rng_(seed, 0, "worlds.ceiling"),
        distractors_rng_(seed, 0, "worlds.distractors"),
        textures_rng_(seed, 0, "worlds.textures"),
        plain_rng_(seed, 0, "worlds.ceiling.plain") {
    w_.options = options;
    w_.seed = seed;
    DrawAppearance(RandomStream(seed, 0, "worlds.appearance"));
  }

  World Build() {
    if (auto problem = PlanLayout(s_, next_id_, &plan_)) throw OptionsError(*problem);
    next_id_ += static_cast<int>(plan_.segments.size() + plan_.walls.size());
    w_.segments = plan_.segments;
    w_.walls = plan_.walls;
    occupied_.assign(w_.walls.size(), {});
    reflector_cuts_.assign(w_.walls.size(), {});
    door_cuts_.assign(w_.walls.size(), {});

    MakeBaseMaterials();
    PlaceDoors();
    PlacePlates();
    PlaceLamps();
    PlaceReflectors();
    BuildWalls();
    BuildFloorAndCeiling();
    PlaceCeilingFixtures();
    PlaceDistractors();
    Finish();
    return std::move(w_);
  }

 private:
  // ---- appearance randomisation ------------------------------------------------------------
  // Every value is drawn whatever its spread (a spread of 0 draws the multiplier 1), in a fixed
  // order, so turning one factor on leaves the others' draws as they were.
  void DrawAppearance(RandomStream rng) {
    const AppearanceOptions& a = s_.appearance;
    AppearanceDraw& d = w_.appearance;
    auto spread = [&](double s) { return rng.Uniform(1.0 - s, 1.0 + s); };
    for (Eigen::Vector3f* colour : {&d.wall, &d.floor, &d.ceiling, &d.door}) {
      const double brightness = spread(a.surface_brightness);
      for (int c = 0; c < 3; ++c) {
        (*colour)[c] = static_cast<float>(brightness * spread(a.surface_tint));
      }
    }
    d.lamp_brightness = spread(a.lamp_brightness);
    const double t = rng.Uniform(0, 1);
    if (a.lamp_temperature_max_k > 0) {
      d.lamp_temperature_k =
          a.lamp_temperature_min_k + t * (a.lamp_temperature_max_k - a.lamp_temperature_min_k);
      d.lamp_colour = BlackBodyColour(d.lamp_temperature_k);
    }
    d.distractor_density = rng.Uniform(1.0 - a.distractor_density, 1.0);
    d.camera_exposure = spread(a.camera_exposure);
    d.camera_noise = rng.Uniform(1.0, 1.0 + a.camera_noise);
    d.camera_blur_px = rng.Uniform(0.0, a.camera_blur_max_px);
  }

  // A plate colour and a text colour (RGB, 0-255) whose luminances differ by at least 100:
  // both uniform, the text drawn again up to 64 times, then black or white, whichever differs
  // more.
  static std::array<Vector3d, 2> PlateColours(RandomStream& rng) {
    const auto luma = [](const Vector3d& c) {
      return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    };
    const auto draw = [&] {
      // One draw per statement: the order of a call's arguments is the compiler's (docs/worlds.md).
      const double b = rng.Uniform(0, 255), g = rng.Uniform(0, 255), r = rng.Uniform(0, 255);
      return Vector3d(r, g, b);
    };
    const Vector3d plate = draw();
    for (int k = 0; k < 64; ++k) {
      const Vector3d text = draw();
      if (std::abs(luma(plate) - luma(text)) >= 100) return {plate, text};
    }
    return {plate, luma(plate) > 127.5 ? Vector3d::Zero() : Vector3d::Constant(255)};
  }

  // ---- materials, textures, meshes -------------------------------------------------------
  int AddTexture(std::string name, Image8 image) {
    w_.textures.push_back(Texture{std::move(name), std::move(image)});
    return static_cast<int>(w_.textures.size()) - 1;
  }
  int AddMaterial(Material m) {
    w_.materials.push_back(std::move(m));
    return static_cast<int>(w_.materials.size()) - 1;
  }
  int PlainMaterial(const std::string& name, Eigen::Vector3f diffuse, float specular = 0.0f) {
    Material m;
    m.name = name;
    m.diffuse = diffuse;
    m.specular = specular;
    return AddMaterial(m);
  }
  int TexturedMaterial(const std::string& name, int texture, Eigen::Vector3f tint = {1, 1, 1}) {
    Material m;
    m.name = name;
    m.texture = texture;
    m.diffuse = tint;
    return AddMaterial(m);
  }
  Mesh& NewMesh(std::string name, int material, int instance_id, SemanticClass cls) {
    Mesh m;
    m.name = std::move(name);
    m.material = material;
    m.instance_id = instance_id;
    m.semantic_class = cls;
    w_.meshes.push_back(std::move(m));
    return w_.meshes.back();
  }
  void Collide(const AlignedBox3d& box, int instance_id, SemanticClass cls) {
    w_.collision_boxes.push_back(CollisionBox{box.center(), box.sizes() / 2, instance_id, cls});
  }
  // A solid box: drawn and collided.
  void Solid(const std::string& name, int material, int id, SemanticClass cls,
             const AlignedBox3d& box, double uv_period = kWallPeriodM) {
    AddBox(NewMesh(name, material, id, cls), box, uv_period);
    Collide(box, id, cls);
  }

  void MakeBaseMaterials() {
    const int px = s_.texture_px_per_m;
    const int wall_tex = AddTexture("wall", MakeWallTexture(textures_rng_, int(px * kWallPeriodM)));
    const int floor_tex =
        AddTexture("floor", MakeFloorTexture(textures_rng_, int(px * kFloorPeriodM), 4));
    const int ceiling_px = int(px * s_.ceiling.tile_size_m) * kCeilingTilesPerTexture;
    const int ceiling_tex = AddTexture(
        "ceiling", MakeCeilingTexture(textures_rng_, ceiling_px, kCeilingTilesPerTexture));
    const int room_ceiling_tex =
        AddTexture("room_ceiling", MakeRoomCeilingTexture(textures_rng_, int(px * kWallPeriodM)));
    const int door_tex = AddTexture("door_leaf", MakeDoorTexture(textures_rng_, 128, 256));
    const int vent_tex = AddTexture("vent", MakeVentTexture(96));
    // Plain corridor walls: drawn last, from a stream of their own, so that the other textures
    // stay what they are.
    int corridor_wall_tex = wall_tex;
    if (s_.wall_finish == WallFinish::kPlain) {
      RandomStream plain_walls(w_.seed, 0, "worlds.walls.plain");
      corridor_wall_tex =
          AddTexture("wall_plain", MakePlainWallTexture(plain_walls, int(px * kWallPeriodM)));
    }
    const AppearanceDraw& look = w_.appearance;  // 1 without appearance randomisation
    mat_.wall = TexturedMaterial("wall", corridor_wall_tex, look.wall);
    mat_.room_wall = TexturedMaterial("room_wall", wall_tex,
                                      Vector3f(0.95f, 0.9f, 0.8f).cwiseProduct(look.wall));
    mat_.floor = TexturedMaterial("floor", floor_tex, look.floor);
    mat_.room_floor = TexturedMaterial("room_floor", floor_tex,
                                       Vector3f(0.8f, 0.85f, 0.95f).cwiseProduct(look.floor));
    mat_.ceiling = TexturedMaterial("ceiling", ceiling_tex, look.ceiling);
    mat_.room_ceiling = TexturedMaterial("room_ceiling", room_ceiling_tex, look.ceiling);
    mat_.door_leaf = TexturedMaterial("door_leaf", door_tex, look.door);
    mat_.frame = PlainMaterial("door_frame", {0.35f, 0.33f, 0.32f}, 0.2f);
    mat_.vent = TexturedMaterial("vent", vent_tex);
    mat_.detector = PlainMaterial("smoke_detector", {0.95f, 0.95f, 0.95f});
    mat_.sprinkler = PlainMaterial("sprinkler", {0.75f, 0.7f, 0.55f}, 0.6f);
    mat_.mirror = PlainMaterial("reflector", {0.55f, 0.58f, 0.62f}, 0.9f);
    mat_.extinguisher = PlainMaterial("fire_extinguisher", {0.8f, 0.05f, 0.05f}, 0.4f);
    mat_.furniture = PlainMaterial("furniture", {0.45f, 0.32f, 0.2f});
    mat_.metal = PlainMaterial("cabinet_body", {0.6f, 0.6f, 0.62f}, 0.3f);
    Material lamp;
    lamp.name = "lamp_on";
    lamp.diffuse = {1.0f, 1.0f, 0.97f};
    lamp.emission = Vector3f(1.0f, 0.98f, 0.92f).cwiseProduct(w_.appearance.lamp_colour);
    mat_.lamp_on = AddMaterial(lamp);
    mat_.lamp_off = PlainMaterial("lamp_off", {0.55f, 0.55f, 0.55f}, 0.3f);
  }

  // ---- wall coordinates ------------------------------------------------------------------
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
  bool IsFree(int wall, double lo, double hi) const {
    return std::none_of(occupied_[wall].begin(), occupied_[wall].end(),
                        [&](const Interval& iv) { return lo < iv.hi && iv.lo < hi; });
  }
  // Whether `area` (a footprint including its walls) runs into a room, a mirror volume or the
  // walkable corridor.
  bool OverlapsRoomsOrCorridors(const AlignedBox2d& area) const {
    for (const auto& r : room_areas_) {
      if (Overlaps(area, r)) return true;
    }
    for (const auto& c : plan_.segment_rects) {
      if (Overlaps(area, c)) return true;
    }
    return false;
  }

  // ---- doorways ---------------------------------------------------------------------------
  void PlaceDoors() {
    const DoorOptions& d = s_.doors;
    const double f = plan_.door_footprint_m, g = d.min_gap_m, t = s_.wall_thickness_m;
    const double weights[] = {d.closed_weight, d.open_weight, d.empty_weight};
    const DoorState states[] = {DoorState::kClosed, DoorState::kOpen, DoorState::kEmpty};
    for (std::size_t k = 0; k < w_.walls.size(); ++k) {
      const int n = plan_.doors_per_wall[k];
      if (n == 0) continue;
      const Wall& wall = w_.walls[k];
      // Stick breaking: the slack beyond minimum spacing is split at n sorted uniform points.
      const double slack = UsableWallLength(wall, s_) - n * f - (n - 1) * g;
      std::vector<double> cuts(n);
      for (double& c : cuts) c = doors_rng_.Uniform(0, std::max(0.0, slack));
      std::sort(cuts.begin(), cuts.end());
      for (int i = 0; i < n; ++i) {
        const double start = g + i * (f + g) + cuts[i];
        Doorway door;
        door.id = next_id_++;
        door.wall_id = wall.id;
        door.state = states[doors_rng_.Categorical(weights)];
        door.column_a = OnWall(wall, start + d.frame_width_m / 2, 0);
        door.column_b = OnWall(wall, start + f - d.frame_width_m / 2, 0);
        door.inward_normal = wall.inward_normal;
        door.width_m = d.width_m;
        door.top_height_m = d.height_m;
        door.column_width_m = d.frame_width_m;
        if (door.state != DoorState::kClosed) {
          // The room is room_width_m wide, narrowed where needed to stop half-way to the
          // neighbouring doorways on this wall (less its wall), so that rooms of close doors
          // share a wall instead of turning each other's doors into closed ones.
          const double centre = start + f / 2;
          const double half = std::max(d.room_width_m, f + 0.4) / 2;
          double lo = centre - half, hi = centre + half;
          if (i > 0) lo = std::max(lo, (g + (i - 1) * (f + g) + cuts[i - 1] + f + start) / 2 + t);
          if (i + 1 < n)
            hi = std::min(hi, (start + f + g + (i + 1) * (f + g) + cuts[i + 1]) / 2 - t);
          const AlignedBox2d area = WallRect(wall, lo, hi, -t, -t - d.room_depth_m);
          if (OverlapsRoomsOrCorridors(Inflated(area, t))) {
            door.state = DoorState::kClosed;  // no space behind this wall for a room
          } else {
            door.room = Room{area, d.room_height_m};
            room_areas_.push_back(Inflated(area, t));
          }
        }
        occupied_[k].push_back({start - 0.05, start + f + 0.05});
        door_cuts_[k].push_back({start, start + f});
        door_walls_.push_back(static_cast<int>(k));
        door_starts_.push_back(start);
        w_.doors.push_back(door);
      }
    }
    // Room numbers run along the walls with occasional skipped numbers, so they are unique.
    int floor = s_.plates.first_floor;
    if (floor == 0) floor = static_cast<int>(plates_rng_.UniformInt(1, 9));
    int number = floor * 100;
    for (Doorway& door : w_.doors) {
      number += static_cast<int>(plates_rng_.UniformInt(1, 2));
      door.room_number = std::to_string(number);
    }
    for (std::size_t i = 0; i < w_.doors.size(); ++i) BuildDoor(i);
  }

  void BuildDoor(std::size_t index) {
    const Doorway& door = w_.doors[index];
    const Wall& wall = w_.walls[door_walls_[index]];
    const DoorOptions& d = s_.doors;
    const double start = door_starts_[index], f = plan_.door_footprint_m;
    const double t = s_.wall_thickness_m, p = d.frame_protrusion_m, fw = d.frame_width_m;
    const double bar_top = d.height_m + d.bar_height_m;
    const int id = door.id;
    // Columns and top bar: the door feature of P2/P3.
    Solid(Id("door_column_a", id), mat_.frame, id, SemanticClass::kDoorFrame,
          WallBox(wall, start, start + fw, -kSeam, bar_top, -t - p, p));
    Solid(Id("door_column_b", id), mat_.frame, id, SemanticClass::kDoorFrame,
          WallBox(wall, start + f - fw, start + f, -kSeam, bar_top, -t - p, p));
    Solid(Id("door_bar", id), mat_.frame, id, SemanticClass::kDoorFrame,
          WallBox(wall, start + fw, start + f - fw, d.height_m, bar_top, -t - p, p));
    Solid(Id("door_header", id), mat_.wall, wall.id, SemanticClass::kWall,
          WallBox(wall, start, start + f, bar_top, s_.height_m + kSeam, -t, 0));
    if (door.state == DoorState::kClosed) {
      Solid(Id("door_leaf", id), mat_.door_leaf, id, SemanticClass::kDoorLeaf,
            WallBox(wall, start + fw, start + f - fw, -kSeam, d.height_m, -t / 2 - 0.02,
                    -t / 2 + 0.02),
            d.height_m);
    } else if (door.state == DoorState::kOpen) {
      // The leaf swung by 90 degrees into the room, hinged at column a.
      Solid(Id("door_leaf", id), mat_.door_leaf, id, SemanticClass::kDoorLeaf,
            WallBox(wall, start + fw, start + fw + 0.04, -kSeam, d.height_m - 0.01, -t - d.width_m,
                    -t),
            d.height_m);
    }
    if (door.room) BuildRoom(door, wall);
  }

  void BuildRoom(const Doorway& door, const Wall& wall) {
    const Room& room = *door.room;
    const double t = s_.wall_thickness_m, h = room.ceiling_height_m;
    const int id = door.id;
    // The room's floor runs under the doorway's threshold up to the corridor's floor.
    AlignedBox2d floor_area = room.footprint;
    floor_area.extend(
        room.footprint.center() +
        wall.inward_normal *
            (room.footprint.sizes().dot(wall.inward_normal.cwiseAbs()) / 2 + s_.wall_thickness_m));
    Mesh& floor = NewMesh(Id("room_floor", id), mat_.room_floor, id, SemanticClass::kRoom);
    AddHorizontalRect(floor, floor_area, 0.0, true, kFloorPeriodM);
    // A strip kSeam either side of the edge, 0.5 mm below: the two floors meet edge to edge in
    // one plane, with T-junctions between their patches that can open one-pixel holes onto the
    // void; a ray through such a hole meets the strip (hidden everywhere else).
    const Vector2d edge =
        floor_area.center() + wall.inward_normal.cwiseProduct(floor_area.sizes() / 2);
    AlignedBox2d strip = floor_area;
    for (int a = 0; a < 2; ++a) {
      if (std::abs(wall.inward_normal[a]) < 0.5) continue;
      strip.min()[a] = edge[a] - kSeam;
      strip.max()[a] = edge[a] + kSeam;
    }
    AddHorizontalRect(floor, strip, -0.0005, true, kFloorPeriodM);
    Mesh& ceiling = NewMesh(Id("room_ceiling", id), mat_.room_ceiling, id, SemanticClass::kRoom);
    AddHorizontalRect(ceiling, room.footprint, h, false, kWallPeriodM);
    // Three walls; the fourth is the back of the corridor wall.
    const AlignedBox2d outer = Inflated(room.footprint, t);
    const Vector2d n = wall.inward_normal;
    const Vector2d lo = outer.min(), hi = outer.max(), ilo = room.footprint.min(),
                   ihi = room.footprint.max();
    std::vector<AlignedBox2d> sides;
    if (std::abs(n.x()) > 0.5) {  // wall runs along y; the room extends along -n.x
      sides.emplace_back(Vector2d(lo.x(), lo.y()), Vector2d(hi.x(), ilo.y()));
      sides.emplace_back(Vector2d(lo.x(), ihi.y()), Vector2d(hi.x(), hi.y()));
      sides.push_back(n.x() > 0
                          ? AlignedBox2d(Vector2d(lo.x(), ilo.y()), Vector2d(ilo.x(), ihi.y()))
                          : AlignedBox2d(Vector2d(ihi.x(), ilo.y()), Vector2d(hi.x(), ihi.y())));
    } else {
      sides.emplace_back(Vector2d(lo.x(), lo.y()), Vector2d(ilo.x(), hi.y()));
      sides.emplace_back(Vector2d(ihi.x(), lo.y()), Vector2d(hi.x(), hi.y()));
      sides.push_back(n.y() > 0
                          ? AlignedBox2d(Vector2d(ilo.x(), lo.y()), Vector2d(ihi.x(), ilo.y()))
                          : AlignedBox2d(Vector2d(ilo.x(), ihi.y()), Vector2d(ihi.x(), hi.y())));
    }
    for (std::size_t k = 0; k < sides.size(); ++k) {
      const AlignedBox3d box(Vector3d(sides[k].min().x(), sides[k].min().y(), -kSeam),
                             Vector3d(sides[k].max().x(), sides[k].max().y(), h + kSeam));
      Solid(Id("room_wall", id) + "_" + std::to_string(k), mat_.room_wall, id, SemanticClass::kRoom,
            box);
    }
    if (s_.lamps.room_lamps) {
      const Vector2d c = room.footprint.center();
      const double r = (s_.lamps.radius_min_m + s_.lamps.radius_max_m) / 2;
      AddLamp(Vector3d(c.x(), c.y(), h - kLampDrop), LampShape::kCircular, r, {0, 0}, door.id);
    }
  }

  // ---- door plates ------------------------------------------------------------------------
  void PlacePlates() {
    const PlateOptions& p = s_.plates;
    std::vector<std::size_t> order(w_.doors.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    plates_rng_.Shuffle(order);
    order.resize(static_cast<std::size_t>(p.count));
    std::sort(order.begin(), order.end());
    for (const std::size_t i : order) {
      const Doorway& door = w_.doors[i];
      const int wall_index = door_walls_[i];
      const Wall& wall = w_.walls[wall_index];
      const double scale = 1.0 + plates_rng_.Uniform(-p.size_jitter, p.size_jitter);
      const double width = p.width_m * scale, height = p.height_m * scale;
      const bool before = plates_rng_.Bernoulli(0.5);  // beside column a, or beside column b
      const double s_centre =
          before ? door_starts_[i] - p.gap_from_frame_m - width / 2
                 : door_starts_[i] + plan_.door_footprint_m + p.gap_from_frame_m + width / 2;
      DoorPlate plate;
      plate.id = next_id_++;
      plate.door_id = door.id;
      plate.room_number = door.room_number;
      const double depth = 0.006;
      const Vector2d c = OnWall(wall, s_centre, depth + kSurfaceOffset);
      // Appearance randomisation: each plate's own stream, so the plates do not shift each other.
      RandomStream look(w_.seed, static_cast<std::uint64_t>(plate.id), "worlds.appearance.plate");
      const double jitter = s_.appearance.plate_height_jitter_m;
      plate.center = Vector3d(c.x(), c.y(), p.center_height_m + look.Uniform(-jitter, jitter));
      std::optional<std::array<Vector3d, 2>> colours;
      const std::array<Vector3d, 2> drawn = PlateColours(look);
      if (s_.appearance.plate_colours) colours = drawn;
      plate.normal = Vector3d(wall.inward_normal.x(), wall.inward_normal.y(), 0);
      plate.size_m = Vector2d(width, height);
      PlateStyle style;  // recorded in the ground truth for detector developers
      plate.texture = AddTexture(
          Id("plate", plate.id),
          MakePlateTexture(textures_rng_, plate.room_number, width / height, &style, colours));
      plate.font = style.font;
      plate.border_px = style.border_px;
      // Texture px -> face metres: the decal maps texture x to right, row 0 to the top.
      if (style.width_px > 0 && style.height_px > 0) {
        const auto face = [&](int x_px, int y_px) {
          return Vector2d((double(x_px) / style.width_px - 0.5) * width,
                          (0.5 - double(y_px) / style.height_px) * height);
        };
        const Vector2d a = face(style.number_x0_px, style.number_y1_px);
        const Vector2d b = face(style.number_x1_px, style.number_y0_px);
        plate.number_min_in_face = a.cwiseMin(b);
        plate.number_max_in_face = a.cwiseMax(b);
      }
      const int material = TexturedMaterial(Id("plate", plate.id), plate.texture);
      const int backing = PlainMaterial(Id("plate_backing", plate.id), {0.3f, 0.3f, 0.3f});
      const double z0 = p.center_height_m - height / 2, z1 = p.center_height_m + height / 2;
      AddBox(NewMesh(Id("plate_backing", plate.id), backing, plate.id, SemanticClass::kDoorPlate),
             WallBox(wall, s_centre - width / 2, s_centre + width / 2, z0, z1, 0, depth), 1.0);
      AddDecal(Id("plate", plate.id), material, plate.id, SemanticClass::kDoorPlate, plate.center,
               plate.normal, width, height);
      occupied_[wall_index].push_back({s_centre - width / 2 - 0.05, s_centre + width / 2 + 0.05});
      w_.plates.push_back(plate);
    }
  }

  // A textured rectangle facing `normal` (horizontal), upright, reading left to right for a
  // viewer in front of it; UV (0,0) at its bottom-left.
  void AddDecal(const std::string& name, int material, int id, SemanticClass cls,
                const Vector3d& centre, const Vector3d& normal, double width, double height) {
    const Vector3d up = Vector3d::UnitZ();
    const Vector3d right = -normal.cross(up);
    AddQuad(NewMesh(name, material, id, cls), centre - right * width / 2 - up * height / 2,
            right * width, up * height);
  }

  // ---- lamps ------------------------------------------------------------------------------
  int AddLamp(const Vector3d& centre, LampShape shape, double radius, const Vector2d& size,
              int room_door_id) {
    Lamp lamp;
    lamp.id = next_id_++;
    lamp.shape = shape;
    lamp.center = centre;
    lamp.radius_m = shape == LampShape::kCircular ? radius : 0.0;
    lamp.size_m = shape == LampShape::kPanel ? size : Vector2d::Zero();
    lamp.on = !lamps_rng_.Bernoulli(s_.lamps.off_fraction);
    lamp.room_door_id = room_door_id;
    const int material = lamp.on ? mat_.lamp_on : mat_.lamp_off;
    if (shape == LampShape::kCircular) {
      Mesh& mesh = NewMesh(Id("lamp", lamp.id), material, lamp.id, SemanticClass::kLampCircular);
      AddDisc(mesh, centre, radius, -Vector3d::UnitZ(), kDiscSegments);
    } else {
      const AlignedBox2d rect(centre.head<2>() - size / 2, centre.head<2>() + size / 2);
      Mesh& mesh = NewMesh(Id("lamp", lamp.id), material, lamp.id, SemanticClass::kLampPanel);
      AddHorizontalRect(mesh, rect, centre.z(), false, 1.0, rect.min());
    }
    w_.lamps.push_back(lamp);
    return lamp.id;
  }

  // Whether point p of segment k lies in the part of the corridor owned by an earlier segment
  // (corner squares, the T's junction).
  bool OwnedByEarlierSegment(std::size_t k, const Vector2d& p, double margin) const {
    for (std::size_t j = 0; j < k; ++j) {
      if (Inflated(plan_.segment_rects[j], margin).contains(p)) return true;
    }
    return false;
  }

  // Whether `box` lies in the walkable area, at least `margin` from every wall.
  bool InsideCorridor(const AlignedBox2d& box, double margin) const {
    const AlignedBox2d grown = Inflated(box, margin);
    for (const Vector2d& corner :
         {grown.min(), grown.max(), Vector2d(grown.min().x(), grown.max().y()),
          Vector2d(grown.max().x(), grown.min().y())}) {
      if (std::none_of(plan_.segment_rects.begin(), plan_.segment_rects.end(),
                       [&](const AlignedBox2d& r) { return r.contains(corner); })) {
        return false;
      }
    }
    return true;
  }

  void PlaceLamps() {
    const LampOptions& l = s_.lamps;
    const double z = s_.height_m - kLampDrop;
    for (std::size_t k = 0; k < w_.segments.size(); ++k) {
      const CorridorSegment& seg = w_.segments[k];
      const double length = (seg.end - seg.start).norm();
      const Vector2d dir = seg.direction();
      for (double s = l.spacing_m / 2; s < length; s += l.spacing_m) {
        const double pos = std::clamp(
            s + lamps_rng_.Uniform(-l.spacing_jitter_m, l.spacing_jitter_m), 0.0, length);
        const Vector2d c = seg.start + pos * dir;
        const bool circular = lamps_rng_.Bernoulli(l.circular_fraction);
        const double radius = lamps_rng_.Uniform(l.radius_min_m, l.radius_max_m);
        const double extent = circular ? radius : l.panel_length_m / 2;
        if (OwnedByEarlierSegment(k, c, extent)) continue;
        Vector2d size(l.panel_length_m, l.panel_width_m);
        if (std::abs(dir.y()) > 0.5) size = Vector2d(l.panel_width_m, l.panel_length_m);
        const Vector2d half = circular ? Vector2d(radius, radius) : Vector2d(size / 2);
        if (!InsideCorridor(AlignedBox2d(c - half, c + half), 0.05)) continue;  // off the walls
        const int id =
            AddLamp(Vector3d(c.x(), c.y(), z), circular ? LampShape::kCircular : LampShape::kPanel,
                    radius, size, -1);
        lamp_segment_.push_back({id, static_cast<int>(k)});
        AddCeilingKeepout(
            circular ? AlignedBox2d(c - Vector2d(radius, radius), c + Vector2d(radius, radius))
                     : AlignedBox2d(c - size / 2, c + size / 2));
      }
    }
  }

  // ---- reflective wall panels mirroring a lamp (P3 Fig. 3b/3c) -----------------------------
  void PlaceReflectors() {
    const LampOptions& l = s_.lamps;
    const double t = s_.wall_thickness_m, H = s_.height_m;
    for (const auto& [lamp_id, segment_index] : lamp_segment_) {
      const Lamp lamp = *std::find_if(w_.lamps.begin(), w_.lamps.end(),
                                      [id = lamp_id](const Lamp& x) { return x.id == id; });
      if (lamp.shape != LampShape::kCircular || !lamp.on) continue;
      if (!lamps_rng_.Bernoulli(l.reflector_fraction)) continue;
      const int side = lamps_rng_.Bernoulli(0.5) ? 1 : -1;
      const int segment_id = w_.segments[segment_index].id;
      for (std::size_t k = 0; k < w_.walls.size(); ++k) {
        const Wall& wall = w_.walls[k];
        if (!wall.side_wall || wall.segment_id != segment_id) continue;
        const Vector2d rel = lamp.center.head<2>() - wall.start;
        const double along = rel.dot(wall.tangent()), dist = rel.dot(wall.inward_normal);
        const Vector2d seg_side(-w_.segments[segment_index].direction().y(),
                                w_.segments[segment_index].direction().x());
        if (wall.inward_normal.dot(seg_side) * side > 0) continue;  // the other wall
        const double s0 = along - l.reflector_length_m / 2, s1 = along + l.reflector_length_m / 2;
        if (dist <= 0 || dist >= s_.width_m || s0 < 0.1 || s1 > wall.length() - 0.1) continue;
        if (!IsFree(static_cast<int>(k), s0 - 0.1, s1 + 0.1)) continue;
        // The mirrored corridor behind the panel must not run into rooms or corridors.
        const double depth = s_.width_m;
        if (OverlapsRoomsOrCorridors(WallRect(wall, s0 - t, s1 + t, 0, -depth - t))) continue;
        room_areas_.push_back(WallRect(wall, s0 - t, s1 + t, 0, -depth - t));
        Reflector r;
        r.id = next_id_++;
        r.wall_id = wall.id;
        r.mirrored_lamp_id = lamp.id;
        const Vector2d face = OnWall(wall, along, 0);
        r.center = Vector3d(face.x(), face.y(), H - l.reflector_height_m / 2);
        r.size_m = Vector2d(l.reflector_length_m, l.reflector_height_m);
        const Vector2d mirrored = lamp.center.head<2>() - 2 * dist * wall.inward_normal;
        r.apparent_lamp_center = Vector3d(mirrored.x(), mirrored.y(), lamp.center.z());
        BuildReflector(r, wall, s0, s1, lamp);
        occupied_[k].push_back({s0 - 0.05, s1 + 0.05});
        reflector_cuts_[k].push_back({s0, s1});
        w_.reflectors.push_back(r);
        break;
      }
    }
  }

  // The panel is an opening in the top of the wall onto the mirror image of the corridor: a
  // mirrored ceiling, the mirrored lamp, and the mirrored far wall (planar mirror by geometry).
  void BuildReflector(const Reflector& r, const Wall& wall, double s0, double s1,
                      const Lamp& lamp) {
    const double t = s_.wall_thickness_m, H = s_.height_m, depth = s_.width_m;
    const double z0 = H - s_.lamps.reflector_height_m;
    const int id = r.id;
    const auto cls = SemanticClass::kReflector;
    AddBox(NewMesh(Id("reflector_far_wall", id), mat_.mirror, id, cls),
           WallBox(wall, s0 - t, s1 + t, z0 - t, H + t, -depth - t, -depth), kWallPeriodM);
    AddBox(NewMesh(Id("reflector_bottom", id), mat_.mirror, id, cls),
           WallBox(wall, s0 - t, s1 + t, z0 - t, z0, -depth - t, -t), kWallPeriodM);
    // The ends stay behind the wall's own faces: an end box reaching the wall plane put its face
    // on the wall band's face beside the panel (coplanar faces of two materials: z-fighting
    // stripes along the panel's ends); the wall band's end faces are the opening's reveals. The
    // top box's underside is the mirrored ceiling (a separate ceiling mesh on the same plane
    // z-fought with it). The boxes run into each other, so their seams cross instead of touching.
    AddBox(NewMesh(Id("reflector_end_a", id), mat_.mirror, id, cls),
           WallBox(wall, s0 - t, s0, z0 - t, H + t, -depth - t, -t), kWallPeriodM);
    AddBox(NewMesh(Id("reflector_end_b", id), mat_.mirror, id, cls),
           WallBox(wall, s1, s1 + t, z0 - t, H + t, -depth - t, -t), kWallPeriodM);
    AddBox(NewMesh(Id("reflector_top", id), mat_.mirror, id, cls),
           WallBox(wall, s0 - t, s1 + t, H, H + t, -depth - t, 0), kWallPeriodM);
    AddDisc(NewMesh(Id("reflector_lamp", id), mat_.lamp_on, id, cls), r.apparent_lamp_center,
            lamp.radius_m, -Vector3d::UnitZ(), kDiscSegments);
  }

  // ---- walls ------------------------------------------------------------------------------
  void BuildWalls() {
    const double t = s_.wall_thickness_m, H = s_.height_m;
    for (std::size_t k = 0; k < w_.walls.size(); ++k) {
      const Wall& wall = w_.walls[k];
      auto cuts = door_cuts_[k];
      std::sort(cuts.begin(), cuts.end(),
                [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
      double s = 0.0;
      int piece = 0;
      cuts.push_back({wall.length(), wall.length()});
      for (const Interval& cut : cuts) {
        if (cut.lo - s > 1e-9) BuildWallPiece(wall, static_cast<int>(k), s, cut.lo, piece++, t, H);
        s = cut.hi;
      }
      // Outer corners: the square behind both wall faces where two walls meet is filled, so no
      // seam between the two wall boxes can show the void behind them. Inner corners (L, T)
      // would put the square into the corridor and are left alone.
      for (const double s0 : {-t, wall.length()}) {
        const AlignedBox2d square = WallRect(wall, s0, s0 + t, 0, -t);
        const bool in_corridor =
            std::any_of(plan_.segment_rects.begin(), plan_.segment_rects.end(),
                        [&](const AlignedBox2d& r) { return Overlaps(square, r); });
        if (in_corridor) continue;
        Solid(Id("wall_corner", wall.id) + (s0 < 0 ? "_start" : "_end"), mat_.wall, wall.id,
              SemanticClass::kWall, WallBox(wall, s0, s0 + t, -kSeam, H + kSeam, -t, 0));
      }
    }
  }

  // A solid stretch of wall [s0, s1]; reflective panels cut its top band.
  void BuildWallPiece(const Wall& wall, int k, double s0, double s1, int piece, double t,
                      double H) {
    const std::string name = Id("wall", wall.id) + "_" + std::to_string(piece);
    Collide(WallBox(wall, s0, s1, 0, H, -t, 0), wall.id, SemanticClass::kWall);
    Mesh& mesh = NewMesh(name, mat_.wall, wall.id, SemanticClass::kWall);
    std::vector<Interval> bands;
    for (const Interval& r : reflector_cuts_[k]) {
      if (r.lo >= s0 && r.hi <= s1) bands.push_back(r);
    }
    if (bands.empty()) {
      AddBox(mesh, WallBox(wall, s0, s1, -kSeam, H + kSeam, -t, 0), kWallPeriodM);
      return;
    }
    const double z_band = H - s_.lamps.reflector_height_m;
    AddBox(mesh, WallBox(wall, s0, s1, -kSeam, z_band, -t, 0), kWallPeriodM);
    std::sort(bands.begin(), bands.end(),
              [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
    double s = s0;
    bands.push_back({s1, s1});
    for (const Interval& band : bands) {
      if (band.lo - s > 1e-9)
        AddBox(mesh, WallBox(wall, s, band.lo, z_band, H + kSeam, -t, 0), kWallPeriodM);
      s = band.hi;
    }
  }

  // ---- floor and ceiling -------------------------------------------------------------------
  void BuildFloorAndCeiling() {
    const double tile = s_.ceiling.tile_size_m;
    const double offset_y = ceiling_rng_.Uniform(0, tile), offset_x = ceiling_rng_.Uniform(0, tile);
    tile_offset_ = Vector2d(offset_x, offset_y);
    for (std::size_t i = 0; i < plan_.floor_cells.size(); ++i) {
      const AlignedBox2d& cell = plan_.floor_cells[i];
      const int floor_id = next_id_++;
      AddHorizontalRect(NewMesh(Id("floor", floor_id), mat_.floor, floor_id, SemanticClass::kFloor),
                        cell, 0.0, true, kFloorPeriodM);
      for (const auto& [rect, plain] : CeilingStretches(cell)) {
        const int ceiling_id = next_id_++;
        Mesh& mesh = NewMesh(Id("ceiling", ceiling_id), plain ? mat_.room_ceiling : mat_.ceiling,
                             ceiling_id, SemanticClass::kCeiling);
        if (plain) {
          AddHorizontalRect(mesh, rect, s_.height_m, false, kWallPeriodM);
          const std::size_t index = plain_ceiling_.size();
          plain_ceiling_.push_back(rect);
          ForKeepoutCells(rect, [&](const std::pair<long, long>& grid) {
            plain_cells_[grid].push_back(index);
          });
        } else {
          AddHorizontalRect(mesh, rect, s_.height_m, false, tile * kCeilingTilesPerTexture,
                            tile_offset_);
        }
      }
    }
  }

  // The cell's ceiling cut along its longer side into stretches of about plain_stretch_m, each
  // plain (plastered like the rooms', no tiles) with chance plain_fraction, neighbours of one
  // kind merged. Without plain stretches the cell is one tiled stretch and nothing is drawn, so
  // such worlds are the ones generated before this option existed.
  std::vector<std::pair<AlignedBox2d, bool>> CeilingStretches(const AlignedBox2d& cell) {
    const CeilingOptions& c = s_.ceiling;
    if (c.plain_fraction <= 0) return {{cell, false}};
    const int axis = cell.sizes().x() >= cell.sizes().y() ? 0 : 1;
    const double length = cell.sizes()[axis];
    // Bounded: the corridor's length (world bounds) over plain_stretch_m >= 0.5 m.
    const int n = std::max(1, static_cast<int>(std::lround(length / c.plain_stretch_m)));
    std::vector<std::pair<AlignedBox2d, bool>> out;
    for (int k = 0; k < n; ++k) {
      const bool plain = plain_rng_.Uniform(0, 1) < c.plain_fraction;
      AlignedBox2d part = cell;
      part.min()[axis] = cell.min()[axis] + length * k / n;
      part.max()[axis] = k + 1 == n ? cell.max()[axis] : cell.min()[axis] + length * (k + 1) / n;
      if (!out.empty() && out.back().second == plain) {
        out.back().first.max()[axis] = part.max()[axis];
      } else {
        out.emplace_back(part, plain);
      }
    }
    return out;
  }

  // Whether p lies on a plain stretch or within `margin` of one: only the stretches filed under
  // the grid cells around p are tested (a corridor has up to thousands of stretches and a
  // million tile corners).
  bool OnPlainCeiling(const Vector2d& p, double margin) const {
    if (plain_ceiling_.empty()) return false;
    bool on = false;
    const AlignedBox2d around(p - Vector2d(margin, margin), p + Vector2d(margin, margin));
    ForKeepoutCells(around, [&](const std::pair<long, long>& grid) {
      const auto it = plain_cells_.find(grid);
      if (it == plain_cells_.end()) return;
      for (const std::size_t i : it->second) {
        on = on || Inflated(plain_ceiling_[i], margin).contains(p);
      }
    });
    return on;
  }

  // ---- ceiling fixtures and corner points ---------------------------------------------------
  bool CeilingFree(const AlignedBox2d& box) const {
    // Only the keepouts filed under the cells the box touches can overlap it (an overlap shares
    // an inner point, which lies in a cell both are filed under).
    const AlignedBox2d query = Inflated(box, 0.05);
    bool free = true;
    ForKeepoutCells(query, [&](const std::pair<long, long>& cell) {
      const auto it = keepout_cells_.find(cell);
      if (it == keepout_cells_.end()) return;
      for (const std::size_t i : it->second) free = free && !Overlaps(query, ceiling_keepout_[i]);
    });
    return free;
  }

  void AddCeilingKeepout(const AlignedBox2d& box) {
    const std::size_t index = ceiling_keepout_.size();
    ceiling_keepout_.push_back(box);
    ForKeepoutCells(
        box, [&](const std::pair<long, long>& cell) { keepout_cells_[cell].push_back(index); });
  }

  template <class Visit>
  static void ForKeepoutCells(const AlignedBox2d& box, Visit visit) {
    const auto cell = [](double v) { return static_cast<long>(std::floor(v / kKeepoutCellM)); };
    for (long i = cell(box.min().x()); i <= cell(box.max().x()); ++i) {
      for (long j = cell(box.min().y()); j <= cell(box.max().y()); ++j) visit({i, j});
    }
  }

  void AddCorner(CornerKind kind, const Vector3d& p) {
    w_.corner_points.push_back(CornerPoint{next_id_++, kind, p});
  }

  void PlaceCeilingFixtures() {
    const CeilingOptions& c = s_.ceiling;
    const LampOptions& l = s_.lamps;
    const double H = s_.height_m;
    const double lamp_extent = std::max(l.radius_max_m, l.panel_width_m / 2);
    const double vent_lane = lamp_extent + 0.1 + c.vent_size_m / 2;  // right of the axis
    const double sprinkler_lane = lamp_extent + 0.25;                // left of the axis
    for (std::size_t k = 0; k < w_.segments.size(); ++k) {
      const CorridorSegment& seg = w_.segments[k];
      const double length = (seg.end - seg.start).norm();
      const Vector2d dir = seg.direction(), left(-dir.y(), dir.x());
      auto along = [&](double spacing, auto&& place) {
        for (double s = ceiling_rng_.Uniform(0.3, 0.7) * spacing; s < length - 0.3; s += spacing)
          place(s);
      };
      along(c.vent_spacing_m, [&](double s) {
        const Vector2d p = seg.start + s * dir - vent_lane * left;
        const double h = c.vent_size_m / 2;
        const AlignedBox2d box(p - Vector2d(h, h), p + Vector2d(h, h));
        if (OwnedByEarlierSegment(k, p, h) || !CeilingFree(box)) return;
        AddCeilingKeepout(box);
        const int id = next_id_++;
        AddHorizontalRect(NewMesh(Id("vent", id), mat_.vent, id, SemanticClass::kVent), box,
                          H - 0.004, false, c.vent_size_m, box.min());
        for (const Vector2d& q : {box.min(), Vector2d(box.max().x(), box.min().y()), box.max(),
                                  Vector2d(box.min().x(), box.max().y())}) {
          AddCorner(CornerKind::kVent, Vector3d(q.x(), q.y(), H - 0.004));
        }
      });
      along(c.sprinkler_spacing_m, [&](double s) {
        const Vector2d p = seg.start + s * dir + sprinkler_lane * left;
        AddRoundFixture(k, p, 0.025, H - 0.01, mat_.sprinkler, SemanticClass::kSprinkler,
                        CornerKind::kSprinkler);
      });
      along(c.smoke_detector_spacing_m, [&](double s) {
        const Vector2d p = seg.start + s * dir - sprinkler_lane * left;
        AddRoundFixture(k, p, 0.06, H - 0.03, mat_.detector, SemanticClass::kSmokeDetector,
                        CornerKind::kSmokeDetector);
      });
    }
    AddTileSeamCorners();
  }

  void AddRoundFixture(std::size_t k, const Vector2d& p, double r, double z, int material,
                       SemanticClass cls, CornerKind kind) {
    const AlignedBox2d box(p - Vector2d(r, r), p + Vector2d(r, r));
    if (OwnedByEarlierSegment(k, p, r) || !CeilingFree(box)) return;
    AddCeilingKeepout(box);
    const int id = next_id_++;
    const std::string name = cls == SemanticClass::kSprinkler ? "sprinkler" : "smoke_detector";
    AddDisc(NewMesh(Id(name.c_str(), id), material, id, cls), Vector3d(p.x(), p.y(), z), r,
            -Vector3d::UnitZ(), 16);
    AddCorner(kind, Vector3d(p.x(), p.y(), z));
  }

  // Crossings of the ceiling tile seams that are visible: away from walls and fixtures.
  void AddTileSeamCorners() {
    const double tile = s_.ceiling.tile_size_m, margin = 0.05;
    for (const AlignedBox2d& cell : plan_.floor_cells) {
      const auto first = [&](double lo, double offset) {
        return static_cast<long>(std::ceil((lo - offset) / tile - 1e-9));
      };
      for (long i = first(cell.min().x(), tile_offset_.x());; ++i) {
        const double x = tile_offset_.x() + double(i) * tile;
        if (x >= cell.max().x() - 1e-9) break;
        for (long j = first(cell.min().y(), tile_offset_.y());; ++j) {
          const double y = tile_offset_.y() + double(j) * tile;
          if (y >= cell.max().y() - 1e-9) break;
          const Vector2d p(x, y);
          if (NearWall(p, margin) || OnPlainCeiling(p, margin)) continue;
          const AlignedBox2d dot(p - Vector2d(0.01, 0.01), p + Vector2d(0.01, 0.01));
          if (!CeilingFree(dot)) continue;
          AddCorner(CornerKind::kTileSeam, Vector3d(x, y, s_.height_m));
        }
      }
    }
  }

  bool NearWall(const Vector2d& p, double margin) const {
    for (const Wall& w : w_.walls) {
      const Vector2d rel = p - w.start;
      const double along = rel.dot(w.tangent()), across = rel.dot(w.inward_normal);
      if (along > -margin && along < w.length() + margin && std::abs(across) < margin) return true;
    }
    return false;
  }

  // ---- distractors ------------------------------------------------------------------------
  struct Slot {
    int wall;
    double s0;  // start along the wall
  };

  // A free stretch of `width` on some side wall, drawn uniformly over all free positions.
  std::optional<Slot> FindSlot(double width, double margin) {
    struct Gap {
      int wall;
      double lo, slack;
    };
    std::vector<Gap> gaps;
    std::vector<double> weights;
    for (std::size_t k = 0; k < w_.walls.size(); ++k) {
      const Wall& wall = w_.walls[k];
      if (!wall.side_wall) continue;
      auto occ = occupied_[k];
      std::sort(occ.begin(), occ.end(),
                [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
      double s = 0.3;
      occ.push_back({wall.length() - 0.3, wall.length()});
      for (const Interval& iv : occ) {
        const double slack = iv.lo - s - width - 2 * margin;
        if (slack > 0) {
          gaps.push_back({static_cast<int>(k), s + margin, slack});
          weights.push_back(slack);
        }
        s = std::max(s, iv.hi);
      }
    }
    if (gaps.empty()) return std::nullopt;
    const Gap& g = gaps[distractors_rng_.Categorical(weights)];
    return Slot{g.wall, g.lo + distractors_rng_.Uniform(0, g.slack)};
  }

  struct DistractorKind {
    const char* key;  // options key, for errors
    SemanticClass cls;
    int count;
  };

  void PlaceDistractors() {
    const DistractorOptions& x = s_.distractors;
    // Appearance randomisation keeps a fraction of each count (1 without it).
    const auto kept = [&](int count) {
      return static_cast<int>(std::lround(count * w_.appearance.distractor_density));
    };
    const DistractorKind kinds[] = {
        {"distractors.bookshelves", SemanticClass::kBookshelf, kept(x.bookshelves)},
        {"distractors.cabinets", SemanticClass::kCabinet, kept(x.cabinets)},
        {"distractors.notice_boards", SemanticClass::kNoticeBoard, kept(x.notice_boards)},
        {"distractors.posters", SemanticClass::kPoster, kept(x.posters)},
        {"distractors.fire_extinguishers", SemanticClass::kFireExtinguisher,
         kept(x.fire_extinguishers)},
    };
    for (const DistractorKind& kind : kinds) {
      for (int n = 0; n < kind.count; ++n) PlaceDistractor(kind, n);
    }
  }

  void PlaceDistractor(const DistractorKind& kind, int n) {
    auto& rng = distractors_rng_;
    Vector3d size;  // along the wall, out of the wall, height
    double z0 = 0.0;
    switch (kind.cls) {
      case SemanticClass::kBookshelf:
        size = {rng.Uniform(0.8, 1.0), 0.35, rng.Uniform(1.8, 2.0)};
        break;
      case SemanticClass::kCabinet:
        size = {rng.Uniform(0.8, 1.0), 0.45, rng.Uniform(1.0, 1.9)};
        break;
      case SemanticClass::kNoticeBoard:
        size = {1.2, 0.03, 0.9};
        z0 = 1.0;
        break;
      case SemanticClass::kPoster: {
        const double w = rng.Uniform(0.45, 0.65);
        size = {w, 0.004, w * 1.414};
        z0 = 1.6 - size.z() / 2;
        break;
      }
      default:
        size = {0.18, 0.18, 0.55};
        z0 = 0.15;
        break;  // fire extinguisher
    }
    const auto slot = FindSlot(size.x(), 0.15);
    if (!slot) {
      throw OptionsError({kind.key, "only " + std::to_string(n) + " of " +
                                        std::to_string(kind.count) +
                                        " fit on the free wall stretches of this world"});
    }
    const Wall& wall = w_.walls[slot->wall];
    const double s0 = slot->s0, s1 = s0 + size.x();
    occupied_[slot->wall].push_back({s0 - 0.05, s1 + 0.05});
    Distractor d;
    d.id = next_id_++;
    d.semantic_class = kind.cls;
    d.wall_id = wall.id;
    const AlignedBox3d box = WallBox(wall, s0, s1, z0, z0 + size.z(), 0, size.y());
    d.center = box.center();
    d.size_m = size;
    d.normal = Vector3d(wall.inward_normal.x(), wall.inward_normal.y(), 0);
    const Vector3d front = d.center + d.normal * (size.y() / 2 + kSurfaceOffset);
    const std::string name = Id(SemanticClassName(kind.cls).c_str(), d.id);
    const int tex_w = 256, tex_h = int(256 * size.z() / size.x());
    switch (kind.cls) {
      case SemanticClass::kBookshelf:
      case SemanticClass::kCabinet: {
        const bool shelf = kind.cls == SemanticClass::kBookshelf;
        Solid(name, shelf ? mat_.furniture : mat_.metal, d.id, kind.cls, box);
        const Image8 image = shelf ? MakeBookshelfTexture(textures_rng_, tex_w, tex_h)
                                   : MakeCabinetTexture(textures_rng_, tex_w, tex_h);
        const int mat = TexturedMaterial(name, AddTexture(name, image));
        AddDecal(name + "_front", mat, d.id, kind.cls, front, d.normal, size.x(), size.z());
        break;
      }
      case SemanticClass::kNoticeBoard:
      case SemanticClass::kPoster: {
        d.text = std::to_string(rng.UniformInt(1, 9999));
        AddBox(NewMesh(name, mat_.frame, d.id, kind.cls), box, 1.0);
        const Image8 image = kind.cls == SemanticClass::kPoster
                                 ? MakePosterTexture(textures_rng_, d.text, tex_w, tex_h)
                                 : MakeNoticeBoardTexture(textures_rng_, d.text, tex_w, tex_h);
        const int mat = TexturedMaterial(name, AddTexture(name, image));
        AddDecal(name + "_front", mat, d.id, kind.cls, front, d.normal, size.x(), size.z());
        break;
      }
      default:
        Solid(name, mat_.extinguisher, d.id, kind.cls, box);
        break;
    }
    w_.distractors.push_back(d);
  }

  // ---- bounds and the ground slab -----------------------------------------------------------
  void Finish() {
    w_.bounds.setEmpty();
    for (Mesh& m : w_.meshes) {
      UpdateBounds(m);
      w_.bounds.extend(m.bounds.min().cast<double>());
      w_.bounds.extend(m.bounds.max().cast<double>());
    }
    AlignedBox3d ground(Vector3d(w_.bounds.min().x(), w_.bounds.min().y(), -0.1),
                        Vector3d(w_.bounds.max().x(), w_.bounds.max().y(), 0.0));
    Collide(ground, 0, SemanticClass::kFloor);
  }

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

}  // namespace

World Generate(const WorldOptions& options, std::uint64_t seed) {
  if (auto problem = options.Check()) throw OptionsError(*problem);
  return Builder(options, seed).Build();
}

}  // namespace corridorsim::worlds
