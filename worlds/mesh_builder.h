#pragma once
// Small helpers that append primitives to a Mesh. Every solid in these worlds is axis-aligned.

#include <Eigen/Geometry>

#include "worlds/world.h"

namespace corridorsim::worlds {

/// Box with world-aligned UVs: each face maps its two world axes divided by `uv_period_m`, so
/// neighbouring boxes continue one texture seamlessly. Faces are split into patches of at most
/// 1 m (each axis split once for the whole box: no T-junctions) for per-vertex lighting.
void AddBox(Mesh& mesh, const Eigen::AlignedBox3d& box, double uv_period_m);

/// Quad with corners origin, origin + u, origin + u + v, origin + v; front face on the side of
/// u x v. UVs: origin (0,0), +u (uv_max.x, 0), +v (0, uv_max.y).
void AddQuad(Mesh& mesh, const Eigen::Vector3d& origin, const Eigen::Vector3d& u,
             const Eigen::Vector3d& v, const Eigen::Vector2d& uv_max = Eigen::Vector2d(1, 1));

/// Axis-aligned horizontal rectangle at height z, facing up (+z) or down, with UVs = (x, y) /
/// uv_period_m shifted by uv_offset_m (so textures line up with world coordinates); split into
/// patches of at most 1 m like boxes.
void AddHorizontalRect(Mesh& mesh, const Eigen::AlignedBox2d& rect, double z, bool facing_up,
                       double uv_period_m,
                       const Eigen::Vector2d& uv_offset_m = Eigen::Vector2d::Zero());

/// Flat disc facing `normal` (unit), as a fan of `segments` triangles; UVs map the disc to the
/// unit square.
void AddDisc(Mesh& mesh, const Eigen::Vector3d& center, double radius,
             const Eigen::Vector3d& normal, int segments);

/// Recomputes mesh.bounds from its positions.
void UpdateBounds(Mesh& mesh);

}  // namespace corridorsim::worlds
