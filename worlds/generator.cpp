// worlds::Generate: WorldOptions + seed -> World. Each concern draws from its own random stream
// (worlds.doors, worlds.plates, ...), so changing one option does not reshuffle the others.
// This file holds the order of the steps (Builder::Build), the appearance draw, the materials,
// textures and meshes every step draws with, the wall stretches taken, and the world's bounds;
// the steps live in the generator_*.cpp files of their concern (generator_internal.h).

#include <algorithm>
#include <string>
#include <utility>

#include "worlds/generator_internal.h"
#include "worlds/mesh_builder.h"
#include "worlds/textures.h"

namespace corridorsim::worlds {
namespace generator_internal {

Builder::Builder(const WorldOptions& options, std::uint64_t seed)
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

World Builder::Build() {
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

// Every value is drawn whatever its spread (a spread of 0 draws the multiplier 1), in a fixed
// order, so turning one factor on leaves the others' draws as they were.
void Builder::DrawAppearance(RandomStream rng) {
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

int Builder::AddTexture(std::string name, Image8 image) {
  w_.textures.push_back(Texture{std::move(name), std::move(image)});
  return static_cast<int>(w_.textures.size()) - 1;
}

int Builder::AddMaterial(Material m) {
  w_.materials.push_back(std::move(m));
  return static_cast<int>(w_.materials.size()) - 1;
}

int Builder::PlainMaterial(const std::string& name, Eigen::Vector3f diffuse, float specular) {
  Material m;
  m.name = name;
  m.diffuse = diffuse;
  m.specular = specular;
  return AddMaterial(m);
}

int Builder::TexturedMaterial(const std::string& name, int texture, Eigen::Vector3f tint) {
  Material m;
  m.name = name;
  m.texture = texture;
  m.diffuse = tint;
  return AddMaterial(m);
}

Mesh& Builder::NewMesh(std::string name, int material, int instance_id, SemanticClass cls) {
  Mesh m;
  m.name = std::move(name);
  m.material = material;
  m.instance_id = instance_id;
  m.semantic_class = cls;
  w_.meshes.push_back(std::move(m));
  return w_.meshes.back();
}

void Builder::Collide(const AlignedBox3d& box, int instance_id, SemanticClass cls) {
  w_.collision_boxes.push_back(CollisionBox{box.center(), box.sizes() / 2, instance_id, cls});
}

// A solid box: drawn and collided.
void Builder::Solid(const std::string& name, int material, int id, SemanticClass cls,
                    const AlignedBox3d& box, double uv_period) {
  AddBox(NewMesh(name, material, id, cls), box, uv_period);
  Collide(box, id, cls);
}

void Builder::MakeBaseMaterials() {
  const int px = s_.texture_px_per_m;
  const int wall_tex = AddTexture("wall", MakeWallTexture(textures_rng_, int(px * kWallPeriodM)));
  const int floor_tex =
      AddTexture("floor", MakeFloorTexture(textures_rng_, int(px * kFloorPeriodM), 4));
  const int ceiling_px = int(px * s_.ceiling.tile_size_m) * kCeilingTilesPerTexture;
  const int ceiling_tex =
      AddTexture("ceiling", MakeCeilingTexture(textures_rng_, ceiling_px, kCeilingTilesPerTexture));
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
  mat_.room_wall =
      TexturedMaterial("room_wall", wall_tex, Vector3f(0.95f, 0.9f, 0.8f).cwiseProduct(look.wall));
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

bool Builder::IsFree(int wall, double lo, double hi) const {
  return std::none_of(occupied_[wall].begin(), occupied_[wall].end(),
                      [&](const Interval& iv) { return lo < iv.hi && iv.lo < hi; });
}

// Whether `area` (a footprint including its walls) runs into a room, a mirror volume or the
// walkable corridor.
bool Builder::OverlapsRoomsOrCorridors(const AlignedBox2d& area) const {
  for (const auto& r : room_areas_) {
    if (Overlaps(area, r)) return true;
  }
  for (const auto& c : plan_.segment_rects) {
    if (Overlaps(area, c)) return true;
  }
  return false;
}

// A textured rectangle facing `normal` (horizontal), upright, reading left to right for a
// viewer in front of it; UV (0,0) at its bottom-left.
void Builder::AddDecal(const std::string& name, int material, int id, SemanticClass cls,
                       const Vector3d& centre, const Vector3d& normal, double width,
                       double height) {
  const Vector3d up = Vector3d::UnitZ();
  const Vector3d right = -normal.cross(up);
  AddQuad(NewMesh(name, material, id, cls), centre - right * width / 2 - up * height / 2,
          right * width, up * height);
}

void Builder::Finish() {
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

}  // namespace generator_internal

World Generate(const WorldOptions& options, std::uint64_t seed) {
  if (auto problem = options.Check()) throw OptionsError(*problem);
  return generator_internal::Builder(options, seed).Build();
}

}  // namespace corridorsim::worlds
