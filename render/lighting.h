#pragma once
// The light of a scene, baked per vertex when the scene is built (docs/rendering.md, "Light"):
// ambient + direct light from every lit lamp, shadowed by the world's solids, + diffuse bounces
// gathered from the scene's surfaces (radiosity over its patches). Mirror volumes behind
// reflectors take the light of the corridor they mirror. Pure CPU, deterministic, no GL.

#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "render/scene.h"
#include "worlds/world.h"

namespace corridorsim::render {

/// The world's solids as seen by light: axis-aligned boxes (walls, door frames and leaves, room
/// walls, furniture: the world's collision boxes less the ground slab), filed in a grid.
class Occluders {
 public:
  explicit Occluders(const worlds::World& world);
  /// Whether the open segment (a, b) passes through a solid (boxes shrunk by 2 mm, so points on
  /// a face do not shadow themselves).
  bool Blocked(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;
  std::size_t size() const { return boxes_.size(); }

 private:
  std::vector<Eigen::AlignedBox3d> boxes_;
  Eigen::Vector2d origin_{0, 0};
  double cell_m_ = 2.0;
  int nx_ = 0, ny_ = 0;
  std::vector<std::vector<int>> cells_;
  mutable std::vector<std::uint32_t> stamp_;  // per box: the query that last tested it
  mutable std::uint32_t query_ = 0;
};

/// Direct light reaching a surface at `point` facing `normal` (unit) from the scene's point
/// lights within options.bake_range_m: intensity * max(0, n.l) / (1 + (d / falloff)^2) per lamp,
/// none through a solid when options.shadows. RGB, no ambient.
Eigen::Vector3d DirectIrradiance(const Scene& scene, const Occluders& occluders,
                                 const Eigen::Vector3d& point, const Eigen::Vector3d& normal);

/// Fills every scene vertex's irradiance (ambient + direct + options.bounces diffuse bounces).
/// Needs scene.vertices, indices, drawables, materials, textures and lights of `world`.
void BakeLighting(const worlds::World& world, Scene* scene);

/// Mean colour of a material's surface (diffuse times the mean of its texture), linear RGB.
Eigen::Vector3d MaterialAlbedo(const Scene& scene, int material);

/// Auto exposure's meter: the mean luminance (Rec. 709 weights) of albedo times baked irradiance
/// over the triangles of the drawables in `visible` (the union of the lists) that face `eye`,
/// each weighted by the solid angle it covers (area cos / d^2); lamps (emissive) left out.
double MeteredLuminance(const Scene& scene, const Eigen::Vector3d& eye,
                        std::span<const std::vector<int>> visible);

}  // namespace corridorsim::render
