// Building a render::Scene by hand (tests and probes that draw without a world): one unlit
// vertex, and one drawable over the indices appended last.
#pragma once

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "render/scene.h"

namespace corridorsim::test {

/// A vertex at `position` (world frame, m) with unit `normal` (world frame) and texture
/// coordinates (u, v), lit by the scene's ambient term only.
inline render::SceneVertex UnlitVertex(const render::Scene& scene, const Eigen::Vector3f& position,
                                       const Eigen::Vector3f& normal, float u, float v) {
  render::SceneVertex vertex{};
  for (int k = 0; k < 3; ++k) {
    vertex.position[k] = position[k];
    vertex.normal[k] = normal[k];
  }
  vertex.uv[0] = u;
  vertex.uv[1] = v;
  for (float& e : vertex.irradiance) e = scene.options.ambient;  // unlit: the ambient term
  return vertex;
}

/// Appends to `scene` the drawable over its indices from `first_index` to the end.
inline void AppendDrawable(render::Scene* scene, std::uint32_t first_index,
                           const Eigen::AlignedBox3f& bounds, int material,
                           std::uint32_t instance_id, std::uint8_t semantic_class) {
  render::Drawable drawable;
  drawable.first_index = first_index;
  drawable.index_count = static_cast<std::uint32_t>(scene->indices.size()) - first_index;
  drawable.material = material;
  drawable.instance_id = instance_id;
  drawable.semantic_class = semantic_class;
  drawable.bounds = bounds;
  scene->drawables.push_back(drawable);
}

}  // namespace corridorsim::test
