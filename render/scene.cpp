#include "render/scene.h"

#include "render/lighting.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace corridorsim::render {
namespace {

using Eigen::Vector3d;

constexpr double kReferenceLampRadiusM = 0.2;  // a lamp of this radius has intensity 1
constexpr float kLightBelowLampM = 0.05f;      // lights sit just below the emitting face

// The six planes of a view frustum, as (normal pointing inside, offset): inside iff n.p + d >= 0.
struct Frustum {
  Eigen::Vector3d normal[6];
  double offset[6];
  Eigen::Vector3d corners[8];  // near then far, world frame

  bool MayIntersect(const Eigen::AlignedBox3f& box) const {
    for (int i = 0; i < 6; ++i) {
      // The box corner furthest along the plane normal (the "positive vertex").
      Vector3d p;
      for (int a = 0; a < 3; ++a) p[a] = normal[i][a] >= 0 ? box.max()[a] : box.min()[a];
      if (normal[i].dot(p) + offset[i] < 0) return false;
    }
    return true;
  }
};

Frustum MakeFrustum(const View& view) {
  Frustum f;
  const Eigen::Matrix3d R = view.world_from_camera.rotation();
  const Vector3d c = view.world_from_camera.translation();
  // Image corners on the plane z = 1 (pixel edges, not centres).
  const double x0 = (-0.5 - view.cx) / view.fx, x1 = (view.width - 0.5 - view.cx) / view.fx;
  const double y0 = (-0.5 - view.cy) / view.fy, y1 = (view.height - 0.5 - view.cy) / view.fy;
  const Vector3d rays[4] = {{x0, y0, 1}, {x1, y0, 1}, {x1, y1, 1}, {x0, y1, 1}};
  for (int k = 0; k < 4; ++k) {
    f.corners[k] = c + R * (rays[k] * view.near_m);
    f.corners[4 + k] = c + R * (rays[k] * view.far_m);
  }
  // Side planes through the camera centre and two adjacent corner rays, facing the ray through
  // the image centre (always inside; the optical axis is not, for a cropped off-centre pass).
  const Vector3d inside = R * Vector3d((x0 + x1) / 2, (y0 + y1) / 2, 1.0);
  for (int k = 0; k < 4; ++k) {
    Vector3d n = R * rays[k].cross(rays[(k + 1) % 4]);
    n.normalize();
    if (n.dot(inside) < 0) n = -n;
    f.normal[k] = n;
    f.offset[k] = -n.dot(c);
  }
  const Vector3d axis = R * Vector3d::UnitZ();
  f.normal[4] = axis;
  f.offset[4] = -axis.dot(c + axis * view.near_m);
  f.normal[5] = -axis;
  f.offset[5] = axis.dot(c + axis * view.far_m);
  return f;
}

// Calls f(cell index) for every culling-grid cell that the rectangle [x0, x1] x [y0, y1] (world
// frame, m) touches, the rectangle clamped to the grid.
template <class F>
void ForEachGridCell(const Scene& scene, double x0, double y0, double x1, double y1, F&& f) {
  auto cell_of = [&](double v, double origin, int n) {
    return std::clamp(static_cast<int>(std::floor((v - origin) / scene.grid_cell_m)), 0, n - 1);
  };
  const int ix0 = cell_of(x0, scene.grid_origin.x(), scene.grid_nx);
  const int ix1 = cell_of(x1, scene.grid_origin.x(), scene.grid_nx);
  const int iy0 = cell_of(y0, scene.grid_origin.y(), scene.grid_ny);
  const int iy1 = cell_of(y1, scene.grid_origin.y(), scene.grid_ny);
  for (int iy = iy0; iy <= iy1; ++iy) {
    for (int ix = ix0; ix <= ix1; ++ix) f(static_cast<std::size_t>(iy) * scene.grid_nx + ix);
  }
}

}  // namespace

Scene BuildScene(const worlds::World& world, const SceneOptions& options) {
  Scene scene;
  scene.options = options;
  for (const worlds::Texture& t : world.textures) scene.textures.push_back(t.image);
  for (const worlds::Material& m : world.materials) {
    scene.materials.push_back(
        SceneMaterial{m.diffuse, m.emission * options.lamp_radiance, m.specular, m.texture});
  }
  for (const worlds::Mesh& mesh : world.meshes) {
    const auto base = static_cast<std::uint32_t>(scene.vertices.size());
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
      SceneVertex v;
      for (int a = 0; a < 3; ++a) {
        v.position[a] = mesh.positions[i][a];
        v.normal[a] = mesh.normals[i][a];
      }
      v.uv[0] = mesh.uvs[i].x();
      v.uv[1] = mesh.uvs[i].y();
      for (float& e : v.irradiance) e = options.ambient;
      scene.vertices.push_back(v);
    }
    // Triangles of a mesh larger than a culling cell go into one drawable per cell (by
    // centroid, cells in a fixed order), so culling a long corridor keeps only what is near.
    std::map<std::pair<long, long>, std::vector<std::uint32_t>> chunks;
    const Eigen::Vector3f extent = mesh.bounds.sizes();
    const bool split = std::max(extent.x(), extent.y()) > options.cull_cell_m;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
      std::pair<long, long> key{0, 0};
      if (split) {
        const Eigen::Vector3f c =
            (mesh.positions[mesh.indices[t]] + mesh.positions[mesh.indices[t + 1]] +
             mesh.positions[mesh.indices[t + 2]]) /
            3.0f;
        key = {static_cast<long>(std::floor(c.x() / options.cull_cell_m)),
               static_cast<long>(std::floor(c.y() / options.cull_cell_m))};
      }
      auto& chunk = chunks[key];
      for (int k = 0; k < 3; ++k) chunk.push_back(mesh.indices[t + static_cast<std::size_t>(k)]);
    }
    for (const auto& [key, indices] : chunks) {
      Drawable d;
      d.mesh = static_cast<int>(&mesh - world.meshes.data());
      d.first_index = static_cast<std::uint32_t>(scene.indices.size());
      d.bounds.setEmpty();
      for (const std::uint32_t index : indices) {
        scene.indices.push_back(base + index);
        d.bounds.extend(mesh.positions[index]);
      }
      d.index_count = static_cast<std::uint32_t>(indices.size());
      d.material = mesh.material;
      d.instance_id = static_cast<std::uint32_t>(mesh.instance_id);
      d.semantic_class = static_cast<std::uint8_t>(mesh.semantic_class);
      scene.drawables.push_back(d);
    }
  }
  for (const worlds::Lamp& lamp : world.lamps) {
    if (!lamp.on) continue;
    const double area = lamp.shape == worlds::LampShape::kCircular
                            ? std::numbers::pi * lamp.radius_m * lamp.radius_m
                            : lamp.size_m.x() * lamp.size_m.y();
    const double reference_area = std::numbers::pi * kReferenceLampRadiusM * kReferenceLampRadiusM;
    PointLight light;
    light.position = lamp.center.cast<float>() - Eigen::Vector3f(0, 0, kLightBelowLampM);
    // Appearance randomisation's lamp brightness and colour (1 and white without it).
    light.intensity = static_cast<float>(options.light_intensity * area / reference_area *
                                         world.appearance.lamp_brightness) *
                      world.appearance.lamp_colour;
    light.lamp_id = lamp.id;
    scene.lights.push_back(light);
  }

  for (std::size_t m = 0; m < scene.materials.size(); ++m) {
    scene.materials[m].albedo = MaterialAlbedo(scene, static_cast<int>(m)).cast<float>();
  }
  if (options.bake_lighting) BakeLighting(world, &scene);

  // Culling grid over the x-y extent of all drawables.
  Eigen::AlignedBox3f all;
  all.setEmpty();
  for (const Drawable& d : scene.drawables) all.extend(d.bounds);
  scene.grid_cell_m = options.cull_cell_m;
  if (scene.drawables.empty()) return scene;
  scene.grid_origin = all.min().head<2>().cast<double>();
  const Eigen::Vector2d extent = (all.max() - all.min()).head<2>().cast<double>();
  scene.grid_nx = std::max(1, static_cast<int>(std::ceil(extent.x() / scene.grid_cell_m)));
  scene.grid_ny = std::max(1, static_cast<int>(std::ceil(extent.y() / scene.grid_cell_m)));
  scene.grid_cells.assign(static_cast<std::size_t>(scene.grid_nx) * scene.grid_ny, {});
  for (std::size_t i = 0; i < scene.drawables.size(); ++i) {
    const auto& b = scene.drawables[i].bounds;
    ForEachGridCell(
        scene, b.min().x(), b.min().y(), b.max().x(), b.max().y(),
        [&](std::size_t cell) { scene.grid_cells[cell].push_back(static_cast<int>(i)); });
  }
  return scene;
}

std::vector<int> VisibleDrawables(const Scene& scene, const View& view) {
  std::vector<int> out;
  if (scene.grid_cells.empty()) return out;
  const Frustum f = MakeFrustum(view);
  Eigen::AlignedBox2d footprint(view.world_from_camera.translation().head<2>());
  for (const auto& corner : f.corners) footprint.extend(corner.head<2>());
  ForEachGridCell(scene, footprint.min().x(), footprint.min().y(), footprint.max().x(),
                  footprint.max().y(), [&](std::size_t cell) {
                    for (const int i : scene.grid_cells[cell]) out.push_back(i);
                  });
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  std::erase_if(out, [&](int i) { return !f.MayIntersect(scene.drawables[i].bounds); });
  return out;
}

std::vector<int> NearestLights(const Scene& scene, const Eigen::Vector3d& point, int max_lights) {
  std::vector<std::pair<double, int>> by_distance;
  by_distance.reserve(scene.lights.size());
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    by_distance.emplace_back((scene.lights[i].position.cast<double>() - point).squaredNorm(),
                             static_cast<int>(i));
  }
  const std::size_t n = std::min(by_distance.size(), static_cast<std::size_t>(max_lights));
  std::partial_sort(by_distance.begin(), by_distance.begin() + static_cast<std::ptrdiff_t>(n),
                    by_distance.end());
  std::vector<int> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back(by_distance[i].second);
  return out;
}

}  // namespace corridorsim::render
