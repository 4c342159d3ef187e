#pragma once
// render::Scene: what the GL backends draw, built from a World as plain data (MuJoCo's mjv_
// scene): one vertex and index buffer, drawables with material and label ids, materials,
// textures, point lights for the lamps, and a grid for culling. Tests inspect it without GL.

#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/image.h"
#include "common/pose.h"
#include "worlds/world.h"

namespace corridorsim::render {

struct SceneVertex {
  float position[3];    // world frame, m
  float normal[3];      // unit, world frame
  float uv[2];          // texture repeats, (0,0) = bottom-left of the image
  float irradiance[3];  // RGB light reaching the surface here: ambient + lamps + bounces (baked)
};

struct SceneMaterial {
  Eigen::Vector3f diffuse{0.8f, 0.8f, 0.8f};  // multiplies the texture
  Eigen::Vector3f emission{0, 0, 0};          // added unlit radiance (lit lamps)
  float specular = 0.0f;
  int texture = -1;                          // index into Scene::textures
  Eigen::Vector3f albedo{0.8f, 0.8f, 0.8f};  // diffuse times the texture's mean (bounces, meter)
};

/// A range of the index buffer drawn with one material: a world mesh, or one culling-cell chunk
/// of a mesh larger than a cell (a long floor or wall), so culling keeps only what is near.
struct Drawable {
  int mesh = 0;  // index of the world mesh it draws (part of)
  std::uint32_t first_index = 0;
  std::uint32_t index_count = 0;
  int material = 0;
  std::uint32_t instance_id = 0;    // World ground-truth id (0 = nothing)
  std::uint8_t semantic_class = 0;  // worlds::SemanticClass
  Eigen::AlignedBox3f bounds;
};

/// A lit lamp as a point light just below its emitting face.
struct PointLight {
  Eigen::Vector3f position;   // world frame, m
  Eigen::Vector3f intensity;  // RGB radiant intensity scale (1 = a 0.2 m lamp at full power)
  int lamp_id = 0;
};

/// How textures are filtered when a surface shows them smaller than their texels.
enum class TextureFilter {
  kTrilinear,  // bilinear in the two nearest mip levels, blended (GL_LINEAR_MIPMAP_LINEAR; near
               // a level change only under the default GALLIVM_PERF, see PinSoftwareRasterizer)
  kNearestMip  // bilinear in the nearest level (GL_LINEAR_MIPMAP_NEAREST): cheaper on llvmpipe,
               // with a visible step in sharpness where the level changes
};

struct SceneOptions {
  float ambient = 0.35f;          // uniform ambient light on diffuse surfaces
  float light_intensity = 0.25f;  // scale of every lamp's point light
  float light_falloff_m = 2.5f;   // distance at which a lamp's light has halved
  float lamp_radiance =
      4.0f;  // scale of the lamps' emitted radiance: a lamp saturates, as on a camera
  double cull_cell_m = 4.0;     // size of the culling grid cells
  bool bake_lighting = true;    // lamps' light baked per vertex (all lamps, no per-pixel cost)
  bool shadows = true;          // baked direct light and bounces stop at solids (walls, doors)
  int bounces = 1;              // baked diffuse bounces between surfaces, 0..3
  double bounce_range_m = 6.0;  // surfaces further apart than this exchange no bounced light
  int max_lights = 4;          // per-pixel lighting when not baked: nearest lamps lighting one pass
                               // (each costs ~1.4 ms per 640x480 pass on llvmpipe)
  double bake_range_m = 15.0;  // lamps further than this from a vertex are left out of its sum
  TextureFilter texture_filter = TextureFilter::kTrilinear;
};

struct Scene {
  std::vector<SceneVertex> vertices;
  std::vector<std::uint32_t> indices;
  std::vector<Drawable> drawables;
  std::vector<SceneMaterial> materials;
  std::vector<Image8> textures;  // RGB, row 0 on top
  std::vector<PointLight> lights;
  SceneOptions options;

  // Culling grid over the world's x-y extent: each cell lists the drawables whose bounds touch it.
  Eigen::Vector2d grid_origin{0, 0};
  double grid_cell_m = 4.0;
  int grid_nx = 0, grid_ny = 0;
  std::vector<std::vector<int>> grid_cells;  // grid_nx * grid_ny, row-major in y

  std::size_t triangle_count() const { return indices.size() / 3; }
};

Scene BuildScene(const worlds::World& world, const SceneOptions& options = {});

/// The near clipping distance of every camera view (m): a surface closer to a camera's optical
/// centre than this is clipped, and the camera sees through it (sim/placement.h keeps cameras
/// farther than this from every wall, solid, floor and ceiling).
inline constexpr double kNearPlaneM = 0.05;

/// A pinhole view frustum (no distortion) in the OpenCV optical convention, for culling and for
/// the backends: the camera sees x right, y down, z forward.
struct View {
  SE3 world_from_camera;
  int width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels; (0,0) is the centre of the top-left pixel
  double near_m = kNearPlaneM;
  double far_m = 60.0;
  bool read_depth = true;  // read back the metric depth buffer (cameras without depth skip it)
};

/// Indices of the drawables whose bounds intersect the view frustum (conservative), in
/// increasing order, using the culling grid. The cost follows what is near, not the world size.
std::vector<int> VisibleDrawables(const Scene& scene, const View& view);

/// Up to `max_lights` lights nearest to `point` (deterministic order: by distance, then id).
std::vector<int> NearestLights(const Scene& scene, const Eigen::Vector3d& point, int max_lights);

}  // namespace corridorsim::render
