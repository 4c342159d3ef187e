#include "worlds/mesh_builder.h"

#include <cmath>
#include <numbers>
#include <vector>

namespace corridorsim::worlds {
namespace {

// Large faces are split into patches no longer than this, so that lighting baked per vertex
// (render::BuildScene) follows the lamps closely enough.
constexpr double kMaxPatchM = 1.0;

using Eigen::Vector2d;
using Eigen::Vector3d;

void PushVertex(Mesh& mesh, const Vector3d& p, const Vector3d& n, const Vector2d& uv) {
  mesh.positions.push_back(p.cast<float>());
  mesh.normals.push_back(n.cast<float>());
  mesh.uvs.push_back(uv.cast<float>());
}

void PushQuadIndices(Mesh& mesh, std::uint32_t base) {
  mesh.indices.insert(mesh.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

}  // namespace

void AddQuad(Mesh& mesh, const Vector3d& origin, const Vector3d& u, const Vector3d& v,
             const Vector2d& uv_max) {
  const Vector3d n = u.cross(v).normalized();
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  PushVertex(mesh, origin, n, {0, 0});
  PushVertex(mesh, origin + u, n, {uv_max.x(), 0});
  PushVertex(mesh, origin + u + v, n, {uv_max.x(), uv_max.y()});
  PushVertex(mesh, origin + v, n, {0, uv_max.y()});
  PushQuadIndices(mesh, base);
}

namespace {

// Splits [lo, hi] into the fewest equal parts no longer than kMaxPatchM.
std::vector<double> Splits(double lo, double hi) {
  const int n = std::max(1, static_cast<int>(std::ceil((hi - lo) / kMaxPatchM - 1e-9)));
  std::vector<double> out(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) out[static_cast<std::size_t>(i)] = lo + (hi - lo) * i / n;
  out.back() = hi;
  return out;
}

}  // namespace

void AddBox(Mesh& mesh, const Eigen::AlignedBox3d& box, double uv_period_m) {
  const Vector3d lo = box.min(), hi = box.max();
  // Each axis is split once for the whole box, so neighbouring faces share their edge vertices
  // (no T-junctions, no cracks).
  const std::vector<double> splits[3] = {Splits(lo.x(), hi.x()), Splits(lo.y(), hi.y()),
                                         Splits(lo.z(), hi.z())};
  for (int axis = 0; axis < 3; ++axis) {
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;
    // UVs: horizontal world axis first and z second on walls, (x, y) on floors and ceilings.
    const int ua = axis == 2 ? 0 : (axis == 0 ? 1 : 0);
    const int va = axis == 2 ? 1 : 2;
    for (int side = 0; side < 2; ++side) {
      Vector3d n = Vector3d::Zero();
      n[axis] = side ? 1.0 : -1.0;
      const auto& sa = splits[a];
      const auto& sb = splits[b];
      for (std::size_t i = 0; i + 1 < sa.size(); ++i) {
        for (std::size_t j = 0; j + 1 < sb.size(); ++j) {
          // Corners in counter-clockwise order seen from outside (a x b is along +axis).
          Vector3d c[4];
          for (auto& corner : c) corner[axis] = side ? hi[axis] : lo[axis];
          const double a0 = sa[i], a1 = sa[i + 1], b0 = sb[j], b1 = sb[j + 1];
          c[0][a] = a0, c[0][b] = b0;
          if (side) {
            c[1][a] = a1, c[1][b] = b0;
            c[2][a] = a1, c[2][b] = b1;
            c[3][a] = a0, c[3][b] = b1;
          } else {
            c[1][a] = a0, c[1][b] = b1;
            c[2][a] = a1, c[2][b] = b1;
            c[3][a] = a1, c[3][b] = b0;
          }
          const auto base = static_cast<std::uint32_t>(mesh.positions.size());
          for (const auto& corner : c) {
            PushVertex(mesh, corner, n, Vector2d(corner[ua], corner[va]) / uv_period_m);
          }
          PushQuadIndices(mesh, base);
        }
      }
    }
  }
}

void AddHorizontalRect(Mesh& mesh, const Eigen::AlignedBox2d& rect, double z, bool facing_up,
                       double uv_period_m, const Vector2d& uv_offset_m) {
  const Vector3d n(0, 0, facing_up ? 1.0 : -1.0);
  const std::vector<double> xs = Splits(rect.min().x(), rect.max().x());
  const std::vector<double> ys = Splits(rect.min().y(), rect.max().y());
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    for (std::size_t j = 0; j + 1 < ys.size(); ++j) {
      Vector2d c[4] = {
          {xs[i], ys[j]}, {xs[i + 1], ys[j]}, {xs[i + 1], ys[j + 1]}, {xs[i], ys[j + 1]}};
      if (!facing_up) std::swap(c[1], c[3]);
      const auto base = static_cast<std::uint32_t>(mesh.positions.size());
      for (const auto& p : c) {
        PushVertex(mesh, Vector3d(p.x(), p.y(), z), n, (p - uv_offset_m) / uv_period_m);
      }
      PushQuadIndices(mesh, base);
    }
  }
}

void AddDisc(Mesh& mesh, const Vector3d& center, double radius, const Vector3d& normal,
             int segments) {
  // An orthonormal basis (e1, e2) of the disc's plane with e1 x e2 = normal.
  const Vector3d helper = std::abs(normal.z()) < 0.9 ? Vector3d::UnitZ() : Vector3d::UnitX();
  const Vector3d e1 = helper.cross(normal).normalized();
  const Vector3d e2 = normal.cross(e1);
  const auto base = static_cast<std::uint32_t>(mesh.positions.size());
  PushVertex(mesh, center, normal, {0.5, 0.5});
  for (int k = 0; k < segments; ++k) {
    const double angle = 2 * std::numbers::pi * k / segments;
    const double c = std::cos(angle), s = std::sin(angle);
    PushVertex(mesh, center + radius * (c * e1 + s * e2), normal, {0.5 + 0.5 * c, 0.5 + 0.5 * s});
  }
  for (int k = 0; k < segments; ++k) {
    const auto i = static_cast<std::uint32_t>(k);
    mesh.indices.insert(
        mesh.indices.end(),
        {base, base + 1 + i, base + 1 + (i + 1) % static_cast<std::uint32_t>(segments)});
  }
}

void UpdateBounds(Mesh& mesh) {
  mesh.bounds.setEmpty();
  for (const auto& p : mesh.positions) mesh.bounds.extend(p);
}

}  // namespace corridorsim::worlds
