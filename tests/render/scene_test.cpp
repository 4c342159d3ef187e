// Tests render/scene.cpp: the plain render scene built from a World, culling and light choice.
#include "render/scene.h"

#include <algorithm>
#include <cmath>

#include <catch2/catch.hpp>

namespace corridorsim::render {
namespace {

using Eigen::Vector3d;

const worlds::World& DefaultWorld() {
  static const worlds::World world = worlds::Generate(worlds::WorldSpec{}, 7);
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
  REQUIRE(scene.drawables.size() == world.meshes.size());
  std::size_t vertices = 0;
  for (std::size_t i = 0; i < world.meshes.size(); ++i) {
    const worlds::Mesh& m = world.meshes[i];
    const Drawable& d = scene.drawables[i];
    CHECK(d.instance_id == static_cast<std::uint32_t>(m.instance_id));
    CHECK(d.semantic_class == static_cast<std::uint8_t>(m.semantic_class));
    CHECK(d.material == m.material);
    CHECK(d.index_count == m.indices.size());
    // The first triangle's first vertex is the mesh's first referenced vertex.
    const SceneVertex& v = scene.vertices[scene.indices[d.first_index]];
    const Eigen::Vector3f p = m.positions[m.indices[0]];
    CHECK(v.position[0] == p.x());
    CHECK(v.position[1] == p.y());
    CHECK(v.position[2] == p.z());
    vertices += m.positions.size();
  }
  CHECK(scene.vertices.size() == vertices);
  CHECK(scene.triangle_count() == world.triangle_count());
  CHECK(scene.textures.size() == world.textures.size());
  const auto lit = std::count_if(world.lamps.begin(), world.lamps.end(),
                                 [](const worlds::Lamp& l) { return l.on; });
  CHECK(scene.lights.size() == static_cast<std::size_t>(lit));
}

TEST_CASE("switched-off lamps give no light", "[render][scene]") {
  worlds::WorldSpec spec;
  spec.lamps.off_fraction = 0.5;
  const worlds::World world = worlds::Generate(spec, 3);
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
  for (const double x : {1.0, 20.0, 50.0}) {
    for (const double yaw : {0.0, 0.7, 3.1}) {
      const View view = ForwardView(x, yaw);
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
          const double u = view.fx * p.x() / p.z() + view.cx, w = view.fy * p.y() / p.z() + view.cy;
          in_view = u > -0.5 && u < view.width - 0.5 && w > -0.5 && w < view.height - 0.5;
        }
        if (in_view) {
          INFO("x " << x << " yaw " << yaw << " drawable " << i);
          CHECK(std::binary_search(kept.begin(), kept.end(), static_cast<int>(i)));
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

TEST_CASE("a 1 km corridor costs no more per view than the 55 m one", "[render][scene]") {
  worlds::WorldSpec km;
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
