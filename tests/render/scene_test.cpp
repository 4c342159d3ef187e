// Tests render/scene.cpp: the plain render scene built from a World, culling and light choice.
#include "render/scene.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <catch2/catch.hpp>

namespace corridorsim::render {
namespace {

using Eigen::Vector3d;

const worlds::World& DefaultWorld() {
  static const worlds::World world = worlds::Generate(worlds::WorldOptions{}, 7);
  return world;
}

// A forward-looking 640x480 camera at (x, 0, 0.45) with heading `yaw` (rad).
View ForwardView(double x, double yaw = 0.0, double far_m = 60.0) {
  Eigen::Matrix3d r;
  const Vector3d forward(std::cos(yaw), std::sin(yaw), 0), right(std::sin(yaw), -std::cos(yaw), 0);
  r.col(0) = right;
  r.col(1) = forward.cross(right);
  r.col(2) = forward;
  View v;
  v.world_from_camera = SE3(r, Vector3d(x, 0, 0.45));
  v.width = 640;
  v.height = 480;
  v.fx = v.fy = 525;
  v.cx = 319.5;
  v.cy = 239.5;
  v.far_m = far_m;
  return v;
}

TEST_CASE("the scene holds every mesh of the world with its ids and material", "[render][scene]") {
  const worlds::World& world = DefaultWorld();
  const Scene scene = BuildScene(world);
  REQUIRE(scene.drawables.size() >= world.meshes.size());
  std::vector<std::size_t> indices_of_mesh(world.meshes.size(), 0);
  for (const Drawable& d : scene.drawables) {
    REQUIRE(d.mesh >= 0);
    REQUIRE(d.mesh < static_cast<int>(world.meshes.size()));
    const worlds::Mesh& m = world.meshes[static_cast<std::size_t>(d.mesh)];
    CHECK(d.instance_id == static_cast<std::uint32_t>(m.instance_id));
    CHECK(d.semantic_class == static_cast<std::uint8_t>(m.semantic_class));
    CHECK(d.material == m.material);
    indices_of_mesh[static_cast<std::size_t>(d.mesh)] += d.index_count;
    // Every vertex a drawable references lies in its bounds and in its mesh's bounds.
    for (std::uint32_t k = 0; k < d.index_count; ++k) {
      const SceneVertex& v = scene.vertices[scene.indices[d.first_index + k]];
      const Eigen::Vector3f p(v.position[0], v.position[1], v.position[2]);
      CHECK(d.bounds.contains(p));
      CHECK(m.bounds.contains(p));
    }
    // Chunks of a long mesh stay within about one culling cell.
    CHECK(d.bounds.sizes().head<2>().maxCoeff() <=
          std::max(2.0f * static_cast<float>(scene.options.cull_cell_m),
                   m.bounds.sizes().head<2>().minCoeff() + 1.0f));
  }
  std::size_t vertices = 0;
  for (std::size_t i = 0; i < world.meshes.size(); ++i) {
    CHECK(indices_of_mesh[i] == world.meshes[i].indices.size());
    vertices += world.meshes[i].positions.size();
  }
  CHECK(scene.vertices.size() == vertices);
  CHECK(scene.triangle_count() == world.triangle_count());
  CHECK(scene.textures.size() == world.textures.size());
  const auto lit = std::count_if(world.lamps.begin(), world.lamps.end(),
                                 [](const worlds::Lamp& l) { return l.on; });
  CHECK(scene.lights.size() == static_cast<std::size_t>(lit));
}

TEST_CASE("baked lighting sums every lit lamp's Lambert term with distance fall-off",
          "[render][scene]") {
  const worlds::World& world = DefaultWorld();
  SceneOptions direct_only;  // the direct term alone: no shadows, no bounce
  direct_only.shadows = false;
  direct_only.bounces = 0;
  const Scene scene = BuildScene(world, direct_only);
  const SceneOptions& o = scene.options;
  // A reflector's mirror volume is lit as the corridor it mirrors (lighting_test.cpp).
  std::vector<bool> mirrored;
  for (const worlds::Mesh& mesh : world.meshes) {
    mirrored.insert(mirrored.end(), mesh.positions.size(),
                    mesh.semantic_class == worlds::SemanticClass::kReflector);
  }
  int checked = 0;
  for (std::size_t i = 0; i < scene.vertices.size(); i += 131) {
    if (mirrored[i]) continue;
    const SceneVertex& v = scene.vertices[i];
    const Vector3d p(v.position[0], v.position[1], v.position[2]);
    const Vector3d n(v.normal[0], v.normal[1], v.normal[2]);
    double expected = o.ambient;
    for (const worlds::Lamp& lamp : world.lamps) {
      if (!lamp.on) continue;
      const double area = lamp.shape == worlds::LampShape::kCircular
                              ? std::numbers::pi * lamp.radius_m * lamp.radius_m
                              : lamp.size_m.x() * lamp.size_m.y();
      const double intensity = o.light_intensity * area / (std::numbers::pi * 0.2 * 0.2);
      const Vector3d l = lamp.center - Vector3d(0, 0, 0.05) - p;
      if (l.norm() > o.bake_range_m) continue;
      expected += intensity * std::max(0.0, n.dot(l.normalized())) /
                  (1.0 + l.squaredNorm() / (o.light_falloff_m * o.light_falloff_m));
    }
    for (int c = 0; c < 3; ++c) CHECK(v.irradiance[c] == Approx(expected).epsilon(1e-4));
    ++checked;
  }
  CHECK(checked > 50);
  // Without baking every vertex carries the ambient term alone.
  SceneOptions unbaked;
  unbaked.bake_lighting = false;
  const Scene flat = BuildScene(world, unbaked);
  for (std::size_t i = 0; i < flat.vertices.size(); i += 97) {
    for (int c = 0; c < 3; ++c) CHECK(flat.vertices[i].irradiance[c] == unbaked.ambient);
  }
}

TEST_CASE("switched-off lamps give no light", "[render][scene]") {
  worlds::WorldOptions world_options;
  world_options.lamps.off_fraction = 0.5;
  const worlds::World world = worlds::Generate(world_options, 3);
  const Scene scene = BuildScene(world);
  std::size_t on = 0;
  for (const auto& l : world.lamps) on += l.on;
  CHECK(on < world.lamps.size());
  CHECK(scene.lights.size() == on);
}

// Conservative culling: every drawable with a vertex that projects into the image in front of
// the camera (within far) is kept.
TEST_CASE("culling keeps every drawable with a vertex in view", "[render][scene]") {
  const Scene scene = BuildScene(DefaultWorld());
  // Full views, and crops whose principal point lies outside the image (as the cube faces of a
  // fisheye are drawn).
  auto crop = [](View v, int variant) {
    if (variant == 1) v.height = 120, v.cy = 400;  // only the top of the view
    if (variant == 2) v.width = 150, v.cx = -200;  // only a strip right of the axis
    return v;
  };
  for (const double x : {1.0, 20.0, 50.0}) {
    for (const double yaw : {0.0, 0.7, 3.1}) {
      for (const int variant : {0, 1, 2}) {
        const View view = crop(ForwardView(x, yaw), variant);
        const std::vector<int> kept = VisibleDrawables(scene, view);
        CHECK(std::is_sorted(kept.begin(), kept.end()));
        const SE3 camera_from_world = view.world_from_camera.Inverse();
        for (std::size_t i = 0; i < scene.drawables.size(); ++i) {
          const Drawable& d = scene.drawables[i];
          bool in_view = false;
          for (std::uint32_t k = 0; k < d.index_count && !in_view; ++k) {
            const SceneVertex& v = scene.vertices[scene.indices[d.first_index + k]];
            const Vector3d p =
                camera_from_world * Vector3d(v.position[0], v.position[1], v.position[2]);
            if (p.z() <= view.near_m || p.z() >= view.far_m) continue;
            const double u = view.fx * p.x() / p.z() + view.cx,
                         w = view.fy * p.y() / p.z() + view.cy;
            in_view = u > -0.5 && u < view.width - 0.5 && w > -0.5 && w < view.height - 0.5;
          }
          if (in_view) {
            INFO("x " << x << " yaw " << yaw << " crop " << variant << " drawable " << i);
            CHECK(std::binary_search(kept.begin(), kept.end(), static_cast<int>(i)));
          }
        }
      }
    }
  }
}

TEST_CASE("culling drops what is behind the camera", "[render][scene]") {
  const worlds::World& world = DefaultWorld();
  const Scene scene = BuildScene(world);
  const View view = ForwardView(40.0);
  const std::vector<int> kept = VisibleDrawables(scene, view);
  for (const int i : kept) CHECK(scene.drawables[i].bounds.max().x() >= 40.0 - 1e-3);
  CHECK(kept.size() < scene.drawables.size());
}

TEST_CASE("a 1 km corridor costs no more per view than the 55 m one", "[render][scene][heavy]") {
  worlds::WorldOptions km;
  km.length_m = 1000;
  km.doors.count = 290;
  km.plates.count = 254;
  const Scene long_scene = BuildScene(worlds::Generate(km, 7));
  const Scene short_scene = BuildScene(DefaultWorld());
  auto triangles = [](const Scene& s, const std::vector<int>& kept) {
    std::size_t n = 0;
    for (const int i : kept) n += s.drawables[i].index_count / 3;
    return n;
  };
  // Mid-corridor, looking along it with the default 60 m draw distance.
  const std::size_t long_tris =
      triangles(long_scene, VisibleDrawables(long_scene, ForwardView(500)));
  const std::size_t short_tris =
      triangles(short_scene, VisibleDrawables(short_scene, ForwardView(0.5)));
  INFO("1 km: " << long_tris << " triangles, 55 m: " << short_tris);
  CHECK(long_tris < 2 * short_tris);
  CHECK(long_tris < long_scene.triangle_count() / 5);
}

TEST_CASE("nearest lights are the closest ones, nearest first", "[render][scene]") {
  const Scene scene = BuildScene(DefaultWorld());
  const Vector3d p(20, 0, 1);
  const std::vector<int> lights = NearestLights(scene, p, 4);
  REQUIRE(lights.size() == 4);
  double last = 0;
  for (const int i : lights) {
    const double d = (scene.lights[i].position.cast<double>() - p).norm();
    CHECK(d >= last);
    last = d;
  }
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    if (std::find(lights.begin(), lights.end(), static_cast<int>(i)) != lights.end()) continue;
    CHECK((scene.lights[i].position.cast<double>() - p).norm() >= last - 1e-9);
  }
}

}  // namespace
}  // namespace corridorsim::render
