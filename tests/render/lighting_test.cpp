// Tests render/lighting.cpp: shadows (a lamp behind a wall adds nothing), the diffuse bounce
// (it lights what faces away from every lamp, and grades the ceiling around each lamp), mirror
// volumes lit as the corridor they mirror, and the auto-exposure meter.
#include "render/lighting.h"

#include <algorithm>
#include <cmath>

#include <catch2/catch.hpp>

#include "render/camera_rig.h"
#include "worlds/mesh_builder.h"

namespace corridorsim::render {
namespace {

using Eigen::Vector3d;

// Two 4 x 4 m rooms side by side along x (x in [0, 4] and [4.2, 8.2]), 3 m high, each with a
// floor and a ceiling; optionally a solid wall between them. One lamp on the first room's ceiling.
worlds::World TwoRooms(bool wall) {
  worlds::World w;
  worlds::Material grey;
  grey.name = "grey";
  grey.diffuse = {0.7f, 0.7f, 0.7f};
  w.materials.push_back(grey);
  int id = 1;
  for (const double x0 : {0.0, 4.2}) {
    for (const bool floor : {true, false}) {
      worlds::Mesh m;
      m.name = "m" + std::to_string(id);
      m.material = 0;
      m.instance_id = id++;
      m.semantic_class = floor ? worlds::SemanticClass::kFloor : worlds::SemanticClass::kCeiling;
      worlds::AddHorizontalRect(
          m, Eigen::AlignedBox2d(Eigen::Vector2d(x0, 0), Eigen::Vector2d(x0 + 4, 4)),
          floor ? 0.0 : 3.0, floor, 1.0);
      worlds::UpdateBounds(m);
      w.meshes.push_back(m);
    }
  }
  if (wall) {
    worlds::CollisionBox box;
    box.center = Vector3d(4.1, 2, 1.5);
    box.half_extents = Vector3d(0.1, 3, 2);  // taller and wider than the rooms
    box.instance_id = id++;
    box.semantic_class = worlds::SemanticClass::kWall;
    w.collision_boxes.push_back(box);
  }
  worlds::Lamp lamp;
  lamp.id = id++;
  lamp.center = Vector3d(2, 2, 2.99);
  lamp.radius_m = 0.2;
  w.lamps.push_back(lamp);
  return w;
}

// Irradiance (channel 0) of the scene's vertices with x beyond `x` (the second room).
std::vector<float> SecondRoom(const Scene& scene) {
  std::vector<float> out;
  for (const SceneVertex& v : scene.vertices) {
    if (v.position[0] > 4.1f) out.push_back(v.irradiance[0]);
  }
  return out;
}

TEST_CASE("a lamp behind a wall adds nothing to the light on the other side", "[render][light]") {
  SceneOptions options;
  options.bounces = 2;
  const Scene walled = BuildScene(TwoRooms(true), options);
  const Scene open = BuildScene(TwoRooms(false), options);
  const std::vector<float> behind = SecondRoom(walled), seen = SecondRoom(open);
  REQUIRE(!behind.empty());
  // Behind the wall: the ambient term exactly, neither direct light nor any bounce.
  for (const float e : behind) CHECK(e == options.ambient);
  // Without the wall the same vertices are lit (the floor directly, the ceiling by the bounce).
  CHECK(*std::min_element(seen.begin(), seen.end()) > options.ambient);
  // And the lamp's own room is lit either way.
  float lit = 0;
  for (const SceneVertex& v : walled.vertices) lit = std::max(lit, v.irradiance[0]);
  CHECK(lit > options.ambient + 0.05f);
}

TEST_CASE("occluders block a segment through a solid, not one beside it or ending on it",
          "[render][light]") {
  const Occluders occluders(TwoRooms(true));
  REQUIRE(occluders.size() == 1);
  CHECK(occluders.Blocked(Vector3d(2, 2, 1), Vector3d(6, 2, 1)));
  CHECK(!occluders.Blocked(Vector3d(2, 2, 1), Vector3d(3.9, 2, 1)));
  CHECK(!occluders.Blocked(Vector3d(2, 2, 1), Vector3d(2, 2, 2.9)));
  CHECK(!occluders.Blocked(Vector3d(2, -1.1, 1), Vector3d(6, -1.1, 1)));  // beside its end
  CHECK(!occluders.Blocked(Vector3d(2, 2, 1), Vector3d(4.0, 2, 1)));      // ends on its face
}

TEST_CASE("the bounce lights surfaces that face away from every lamp", "[render][light]") {
  SceneOptions none, one;
  none.bounces = 0;
  one.bounces = 1;
  const worlds::World world = TwoRooms(false);
  const Scene flat = BuildScene(world, none), bounced = BuildScene(world, one);
  REQUIRE(flat.vertices.size() == bounced.vertices.size());
  int ceiling = 0;
  for (std::size_t i = 0; i < flat.vertices.size(); ++i) {
    const SceneVertex& a = flat.vertices[i];
    const SceneVertex& b = bounced.vertices[i];
    const double from_lamp = std::hypot(a.position[0] - 2.0, a.position[1] - 2.0);
    if (a.normal[2] < -0.5f && a.position[0] < 4.0f && from_lamp > 0.5) {  // room 1's ceiling
      // Above the lamp's light (5 cm below the ceiling) the direct term is small.
      CHECK(a.irradiance[0] < none.ambient + 0.03f);
      CHECK(b.irradiance[0] > a.irradiance[0] + 0.005f);
      ++ceiling;
    }
    for (int c = 0; c < 3; ++c) CHECK(b.irradiance[c] >= a.irradiance[c]);
  }
  CHECK(ceiling >= 9);
}

TEST_CASE("the bounce grades the corridor ceiling around each lamp", "[render][light]") {
  worlds::WorldOptions options;
  options.lamps.reflector_fraction = 0.0;
  const worlds::World world = worlds::Generate(options, 7);
  const Scene scene = BuildScene(world);
  // Ceiling vertices near a lamp's axis against those far from every lamp.
  double near_sum = 0, far_sum = 0;
  int near_n = 0, far_n = 0;
  for (const Drawable& d : scene.drawables) {
    if (d.semantic_class != static_cast<std::uint8_t>(worlds::SemanticClass::kCeiling)) continue;
    for (std::uint32_t k = 0; k < d.index_count; ++k) {
      const SceneVertex& v = scene.vertices[scene.indices[d.first_index + k]];
      double nearest = 1e9;
      for (const worlds::Lamp& l : world.lamps) {
        if (l.on && l.room_door_id < 0) {
          nearest = std::min(
              nearest, std::hypot(l.center.x() - v.position[0], l.center.y() - v.position[1]));
        }
      }
      if (nearest < 0.8) near_sum += v.irradiance[0], ++near_n;
      if (nearest > 1.8) far_sum += v.irradiance[0], ++far_n;
    }
  }
  REQUIRE(near_n > 10);
  REQUIRE(far_n > 10);
  CHECK(near_sum / near_n > 1.1 * (far_sum / far_n));
}

TEST_CASE("a reflector's mirror volume is lit as the corridor it mirrors", "[render][light]") {
  worlds::WorldOptions options;
  options.lamps.reflector_fraction = 1.0;
  const worlds::World world = worlds::Generate(options, 3);
  REQUIRE(!world.reflectors.empty());
  SceneOptions direct_only;
  direct_only.bounces = 0;
  const Scene scene = BuildScene(world, direct_only);
  const Occluders occluders(world);
  std::size_t base = 0;
  int checked = 0;
  for (const worlds::Mesh& mesh : world.meshes) {
    if (mesh.semantic_class == worlds::SemanticClass::kReflector && checked < 200) {
      const auto& r = *std::find_if(world.reflectors.begin(), world.reflectors.end(),
                                    [&](const auto& x) { return x.id == mesh.instance_id; });
      const auto& wall = *std::find_if(world.walls.begin(), world.walls.end(),
                                       [&](const auto& x) { return x.id == r.wall_id; });
      for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        Vector3d p = mesh.positions[i].cast<double>(), n = mesh.normals[i].cast<double>();
        // Behind the wall face, mirrored into the corridor.
        const double behind = (p.head<2>() - wall.start).dot(wall.inward_normal);
        CHECK(behind <= 1e-4);
        p.head<2>() -= 2 * behind * wall.inward_normal;
        n.head<2>() -= 2 * n.head<2>().dot(wall.inward_normal) * wall.inward_normal;
        const Vector3d expected =
            Vector3d::Constant(direct_only.ambient) + DirectIrradiance(scene, occluders, p, n);
        CHECK(scene.vertices[base + i].irradiance[0] == Approx(expected.x()).epsilon(1e-5));
        ++checked;
      }
    }
    base += mesh.positions.size();
  }
  CHECK(checked > 20);
}

TEST_CASE("the auto-exposure meter follows the light in view", "[render][light]") {
  const worlds::World world = worlds::Generate(worlds::WorldOptions{}, 7);
  SceneOptions bright, dim;
  dim.light_intensity = bright.light_intensity / 4;
  dim.ambient = bright.ambient / 4;
  const Scene a = BuildScene(world, bright), b = BuildScene(world, dim);
  std::vector<std::vector<int>> all(1);
  for (std::size_t i = 0; i < a.drawables.size(); ++i) all[0].push_back(static_cast<int>(i));
  const Vector3d eye(5, 0, 1);
  const double la = MeteredLuminance(a, eye, all), lb = MeteredLuminance(b, eye, all);
  CHECK(la > 0);
  CHECK(lb == Approx(la / 4).epsilon(1e-6));   // linear in the light
  CHECK(MeteredLuminance(a, eye, all) == la);  // deterministic
  CHECK(MeteredLuminance(a, eye, std::vector<std::vector<int>>{}) == 0.0);
}

}  // namespace
}  // namespace corridorsim::render

namespace corridorsim::render {
namespace {

TEST_CASE("appearance randomisation's lamp brightness and colour scale every light",
          "[render][light]") {
  worlds::WorldOptions options;
  options.appearance.lamp_brightness = 0.5;
  options.appearance.lamp_temperature_min_k = 2700;
  options.appearance.lamp_temperature_max_k = 3000;
  const worlds::World plain = worlds::Generate(worlds::WorldOptions{}, 8);
  const worlds::World warm = worlds::Generate(options, 8);
  const Scene a = BuildScene(plain), b = BuildScene(warm);
  REQUIRE(a.lights.size() == b.lights.size());
  REQUIRE(!a.lights.empty());
  const Eigen::Vector3f scale =
      static_cast<float>(warm.appearance.lamp_brightness) * warm.appearance.lamp_colour;
  for (std::size_t i = 0; i < a.lights.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      CHECK(b.lights[i].intensity[c] == Approx(a.lights[i].intensity[c] * scale[c]).epsilon(1e-6));
    }
  }
  // Warm light: the floor under a lamp is lit redder than blue.
  const SceneVertex* lit = nullptr;
  for (const SceneVertex& v : b.vertices) {
    if (v.normal[2] > 0.5f && (lit == nullptr || v.irradiance[0] > lit->irradiance[0])) lit = &v;
  }
  REQUIRE(lit != nullptr);
  CHECK(lit->irradiance[0] > lit->irradiance[2] * 1.2f);
}

TEST_CASE("appearance randomisation's camera draws scale exposure, noise and blur",
          "[render][light]") {
  RigOptions rig = RigOptions::Default();
  for (CameraOptions& c : rig.cameras) {
    c.rgb_noise.full_well_electrons = 10000;
    c.rgb_noise.read_noise_electrons = 5;
  }
  rig.cameras[1].noise = false;
  worlds::AppearanceDraw look;
  look.camera_exposure = 1.5;
  look.camera_noise = 2.0;
  look.camera_blur_px = 1.25;
  const RigOptions out = WithAppearance(rig, look);
  for (std::size_t k = 0; k < rig.cameras.size(); ++k) {
    const CameraOptions &before = rig.cameras[k], &after = out.cameras[k];
    CHECK(after.exposure.gain == before.exposure.gain * 1.5);
    if (!before.noise) {
      CHECK(after.rgb_noise.full_well_electrons == before.rgb_noise.full_well_electrons);
      CHECK(after.rgb_noise.motion_blur_px == before.rgb_noise.motion_blur_px);
      continue;
    }
    CHECK(after.rgb_noise.full_well_electrons == 5000);
    CHECK(after.rgb_noise.read_noise_electrons == 10);
    CHECK(after.rgb_noise.motion_blur_px == before.rgb_noise.motion_blur_px + 1.25);
  }
  // Without randomisation the rig is itself.
  const RigOptions same = WithAppearance(rig, worlds::AppearanceDraw{});
  for (std::size_t k = 0; k < rig.cameras.size(); ++k) {
    CHECK(same.cameras[k].exposure.gain == rig.cameras[k].exposure.gain);
    CHECK(same.cameras[k].rgb_noise.full_well_electrons ==
          rig.cameras[k].rgb_noise.full_well_electrons);
    CHECK(same.cameras[k].rgb_noise.motion_blur_px == rig.cameras[k].rgb_noise.motion_blur_px);
  }
}

}  // namespace
}  // namespace corridorsim::render
