#include "render/lighting.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace corridorsim::render {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kShrinkM = 0.002;     // solids shrink by this for shadow tests
constexpr double kLiftM = 0.01;        // rays start and end this far off their surfaces
constexpr double kSourcePatchM = 1.0;  // bounce sources: one per mesh, face and 1 m cell
constexpr double kMinSourceAreaM2 = 1e-4;

// A bounce source: the triangles of one mesh that share a face direction and a 1 m cell.
struct Source {
  Vector3d center = Vector3d::Zero();  // area-weighted centroid
  Vector3d normal = Vector3d::Zero();  // unit
  double area = 0.0;                   // m^2
  Vector3d albedo = Vector3d::Zero();
  Vector3d irradiance = Vector3d::Zero();  // of the light bounced last, area-weighted mean
  std::vector<std::uint32_t> triangles;    // first index of each, into scene.indices
};

bool IsVirtual(worlds::SemanticClass c) {
  // Lamps are lights, not reflectors of light; a reflector's mirror volume is an image.
  return c == worlds::SemanticClass::kLampCircular || c == worlds::SemanticClass::kLampPanel ||
         c == worlds::SemanticClass::kReflector;
}

// Sources filed in an x-y grid of `cell` metres, for gathering within that range.
struct SourceGrid {
  double cell = 6.0;
  std::map<std::pair<long, long>, std::vector<int>> cells;
  std::pair<long, long> CellOf(const Vector3d& p) const {
    return {static_cast<long>(std::floor(p.x() / cell)),
            static_cast<long>(std::floor(p.y() / cell))};
  }
};

// Irradiance at (p, n) from the sources' radiosity B = albedo * irradiance: the point-to-disc
// form factor A cos_p cos_s / (pi r^2 + A), which stays finite where a source is near.
Vector3d Gather(const std::vector<Source>& sources, const SourceGrid& grid,
                const Occluders& occluders, bool shadows, double range, const Vector3d& p,
                const Vector3d& n) {
  Vector3d sum = Vector3d::Zero();
  const auto [cx, cy] = grid.CellOf(p);
  const Vector3d from = p + kLiftM * n;
  for (long dy = -1; dy <= 1; ++dy) {
    for (long dx = -1; dx <= 1; ++dx) {
      const auto it = grid.cells.find({cx + dx, cy + dy});
      if (it == grid.cells.end()) continue;
      for (const int i : it->second) {
        const Source& s = sources[static_cast<std::size_t>(i)];
        const Vector3d r = s.center - p;
        const double d2 = r.squaredNorm();
        if (d2 > range * range || d2 < 1e-12) continue;
        const double d = std::sqrt(d2);
        const double cos_p = n.dot(r) / d, cos_s = -s.normal.dot(r) / d;
        if (cos_p <= 0 || cos_s <= 0) continue;
        const Vector3d b = s.albedo.cwiseProduct(s.irradiance);
        if (b.maxCoeff() <= 0) continue;
        if (shadows && occluders.Blocked(from, s.center + kLiftM * s.normal)) continue;
        sum += b * (s.area * cos_p * cos_s / (std::numbers::pi * d2 + s.area));
      }
    }
  }
  return sum;
}

}  // namespace

// ---- Occluders ---------------------------------------------------------------------------

Occluders::Occluders(const worlds::World& world) {
  Eigen::AlignedBox2d extent;
  extent.setEmpty();
  for (const worlds::CollisionBox& c : world.collision_boxes) {
    if (c.semantic_class == worlds::SemanticClass::kFloor) continue;  // the ground slab
    Vector3d half = c.half_extents - Vector3d::Constant(kShrinkM);
    if (half.minCoeff() <= 0) continue;
    boxes_.emplace_back(c.center - half, c.center + half);
    extent.extend(boxes_.back().min().head<2>());
    extent.extend(boxes_.back().max().head<2>());
  }
  stamp_.assign(boxes_.size(), 0);
  if (boxes_.empty()) return;
  origin_ = extent.min();
  nx_ = std::max(1, static_cast<int>(std::ceil(extent.sizes().x() / cell_m_)) + 1);
  ny_ = std::max(1, static_cast<int>(std::ceil(extent.sizes().y() / cell_m_)) + 1);
  cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
  for (std::size_t i = 0; i < boxes_.size(); ++i) {
    const auto& b = boxes_[i];
    const int x0 = static_cast<int>((b.min().x() - origin_.x()) / cell_m_);
    const int x1 = static_cast<int>((b.max().x() - origin_.x()) / cell_m_);
    const int y0 = static_cast<int>((b.min().y() - origin_.y()) / cell_m_);
    const int y1 = static_cast<int>((b.max().y() - origin_.y()) / cell_m_);
    for (int y = y0; y <= std::min(y1, ny_ - 1); ++y) {
      for (int x = x0; x <= std::min(x1, nx_ - 1); ++x) {
        cells_[static_cast<std::size_t>(y) * nx_ + x].push_back(static_cast<int>(i));
      }
    }
  }
}

bool Occluders::Blocked(const Vector3d& a, const Vector3d& b) const {
  if (boxes_.empty()) return false;
  if (++query_ == 0) {  // the stamps wrapped: start again
    std::fill(stamp_.begin(), stamp_.end(), 0);
    query_ = 1;
  }
  const Vector3d d = b - a;
  auto cell = [&](double v, double o, int n) {
    return std::clamp(static_cast<int>(std::floor((v - o) / cell_m_)), 0, n - 1);
  };
  const int x0 = cell(std::min(a.x(), b.x()), origin_.x(), nx_);
  const int x1 = cell(std::max(a.x(), b.x()), origin_.x(), nx_);
  const int y0 = cell(std::min(a.y(), b.y()), origin_.y(), ny_);
  const int y1 = cell(std::max(a.y(), b.y()), origin_.y(), ny_);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      for (const int i : cells_[static_cast<std::size_t>(y) * nx_ + x]) {
        if (stamp_[static_cast<std::size_t>(i)] == query_) continue;
        stamp_[static_cast<std::size_t>(i)] = query_;
        const auto& box = boxes_[static_cast<std::size_t>(i)];
        // Slab test of the segment a + t d, t in (0, 1).
        double t0 = 0.0, t1 = 1.0;
        bool miss = false;
        for (int k = 0; k < 3 && !miss; ++k) {
          if (std::abs(d[k]) < 1e-15) {
            miss = a[k] <= box.min()[k] || a[k] >= box.max()[k];
            continue;
          }
          double ta = (box.min()[k] - a[k]) / d[k], tb = (box.max()[k] - a[k]) / d[k];
          if (ta > tb) std::swap(ta, tb);
          t0 = std::max(t0, ta);
          t1 = std::min(t1, tb);
          miss = t0 >= t1;
        }
        if (!miss) return true;
      }
    }
  }
  return false;
}

// ---- light -------------------------------------------------------------------------------

Vector3d DirectIrradiance(const Scene& scene, const Occluders& occluders, const Vector3d& point,
                          const Vector3d& normal) {
  const SceneOptions& o = scene.options;
  const double range2 = o.bake_range_m * o.bake_range_m;
  const double inv_falloff2 = 1.0 / (double(o.light_falloff_m) * o.light_falloff_m);
  const Vector3d from = point + kLiftM * normal;
  Vector3d sum = Vector3d::Zero();
  for (const PointLight& light : scene.lights) {
    const Vector3d to_light = light.position.cast<double>() - point;
    const double d2 = std::max(to_light.squaredNorm(), 1e-12);
    if (d2 > range2) continue;
    const double n_dot_l = normal.dot(to_light) / std::sqrt(d2);
    if (n_dot_l <= 0) continue;
    if (o.shadows && occluders.Blocked(from, light.position.cast<double>())) continue;
    sum += light.intensity.cast<double>() * (n_dot_l / (1.0 + d2 * inv_falloff2));
  }
  return sum;
}

Vector3d MaterialAlbedo(const Scene& scene, int material) {
  const SceneMaterial& m = scene.materials[static_cast<std::size_t>(material)];
  Vector3d albedo = m.diffuse.cast<double>();
  if (m.texture >= 0) {
    const Image8& t = scene.textures[static_cast<std::size_t>(m.texture)];
    Vector3d mean = Vector3d::Zero();
    const std::size_t pixels = static_cast<std::size_t>(t.width) * t.height;
    for (std::size_t i = 0; i < pixels; ++i) {
      for (int c = 0; c < 3; ++c) {
        mean[c] += t.data[i * t.channels + static_cast<std::size_t>(std::min(c, t.channels - 1))];
      }
    }
    if (pixels > 0) albedo = albedo.cwiseProduct(mean / (255.0 * double(pixels)));
  }
  return albedo;
}

double MeteredLuminance(const Scene& scene, const Vector3d& eye,
                        std::span<const std::vector<int>> visible) {
  std::vector<int> all;
  for (const auto& list : visible) all.insert(all.end(), list.begin(), list.end());
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  const Vector3d luma(0.2126, 0.7152, 0.0722);
  double sum = 0, weight = 0;
  for (const int index : all) {
    const Drawable& d = scene.drawables[static_cast<std::size_t>(index)];
    const SceneMaterial& m = scene.materials[static_cast<std::size_t>(d.material)];
    if (m.emission.maxCoeff() > 0) continue;
    const Vector3d albedo = m.albedo.cast<double>();
    for (std::uint32_t t = d.first_index; t + 2 < d.first_index + d.index_count; t += 3) {
      const SceneVertex* v[3] = {&scene.vertices[scene.indices[t]],
                                 &scene.vertices[scene.indices[t + 1]],
                                 &scene.vertices[scene.indices[t + 2]]};
      Vector3d p[3], e = Vector3d::Zero();
      for (int k = 0; k < 3; ++k) {
        p[k] = Vector3d(v[k]->position[0], v[k]->position[1], v[k]->position[2]);
        e += Vector3d(v[k]->irradiance[0], v[k]->irradiance[1], v[k]->irradiance[2]) / 3;
      }
      const Vector3d cross = (p[1] - p[0]).cross(p[2] - p[0]);
      const Vector3d r = (p[0] + p[1] + p[2]) / 3 - eye;
      const double d2 = std::max(r.squaredNorm(), 0.01);
      const double projected = -cross.dot(r) / (2 * std::sqrt(d2));  // area * cos
      if (projected <= 0) continue;
      const double w = projected / d2;
      sum += w * luma.dot(albedo.cwiseProduct(e));
      weight += w;
    }
  }
  return weight > 0 ? sum / weight : 0.0;
}

void BakeLighting(const worlds::World& world, Scene* scene) {
  const SceneOptions& o = scene->options;
  const Occluders occluders(world);
  const std::size_t n_vertices = scene->vertices.size();

  // Which mesh each vertex belongs to (BuildScene appends the meshes' vertices in order), and
  // the wall plane of the reflector whose mirror volume it is part of.
  struct Mirror {
    Vector2d point{0, 0}, normal{0, 0};
  };
  std::vector<int> mirror_of(n_vertices, -1);
  std::vector<Mirror> mirrors;
  {
    std::size_t base = 0;
    for (const worlds::Mesh& mesh : world.meshes) {
      if (mesh.semantic_class == worlds::SemanticClass::kReflector) {
        const auto r = std::find_if(world.reflectors.begin(), world.reflectors.end(),
                                    [&](const auto& x) { return x.id == mesh.instance_id; });
        const worlds::Wall* wall = nullptr;
        if (r != world.reflectors.end()) {
          for (const worlds::Wall& w : world.walls) {
            if (w.id == r->wall_id) wall = &w;
          }
        }
        if (wall != nullptr) {
          mirrors.push_back({wall->start, wall->inward_normal});
          for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
            mirror_of[base + i] = static_cast<int>(mirrors.size() - 1);
          }
        }
      }
      base += mesh.positions.size();
    }
  }
  // A vertex's point and normal for lighting: a mirror volume's are reflected into the corridor.
  auto lit_point = [&](std::size_t i) {
    const SceneVertex& v = scene->vertices[i];
    Vector3d p(v.position[0], v.position[1], v.position[2]);
    Vector3d n(v.normal[0], v.normal[1], v.normal[2]);
    if (mirror_of[i] >= 0) {
      const Mirror& m = mirrors[static_cast<std::size_t>(mirror_of[i])];
      const double dp = (p.head<2>() - m.point).dot(m.normal);
      p.head<2>() -= 2 * dp * m.normal;
      n.head<2>() -= 2 * n.head<2>().dot(m.normal) * m.normal;
    }
    return std::make_pair(p, n);
  };

  std::vector<Vector3d> direct(n_vertices);
  for (std::size_t i = 0; i < n_vertices; ++i) {
    const auto [p, n] = lit_point(i);
    direct[i] = DirectIrradiance(*scene, occluders, p, n);
  }

  std::vector<Vector3d> bounced(n_vertices, Vector3d::Zero());
  if (o.bounces > 0) {
    // Sources: real (not virtual) triangles by mesh, face direction and 1 m cell.
    std::vector<Source> sources;
    for (const Drawable& d : scene->drawables) {
      if (IsVirtual(static_cast<worlds::SemanticClass>(d.semantic_class))) continue;
      if (scene->materials[static_cast<std::size_t>(d.material)].emission.maxCoeff() > 0) continue;
      std::map<std::tuple<long, long, long, int>, int> of_key;
      for (std::uint32_t t = d.first_index; t + 2 < d.first_index + d.index_count; t += 3) {
        const auto& a = scene->vertices[scene->indices[t]].position;
        const auto& b = scene->vertices[scene->indices[t + 1]].position;
        const auto& c = scene->vertices[scene->indices[t + 2]].position;
        const Vector3d pa(a[0], a[1], a[2]), pb(b[0], b[1], b[2]), pc(c[0], c[1], c[2]);
        const Vector3d cross = (pb - pa).cross(pc - pa);
        const double area = cross.norm() / 2;
        if (area < kMinSourceAreaM2) continue;
        const Vector3d normal = cross.normalized(), centroid = (pa + pb + pc) / 3;
        int axis = 0;
        normal.cwiseAbs().maxCoeff(&axis);
        const int face = axis * 2 + (normal[axis] > 0 ? 1 : 0);
        const std::tuple<long, long, long, int> key{
            static_cast<long>(std::floor(centroid.x() / kSourcePatchM)),
            static_cast<long>(std::floor(centroid.y() / kSourcePatchM)),
            static_cast<long>(std::floor(centroid.z() / kSourcePatchM)), face};
        auto [it, fresh] = of_key.try_emplace(key, static_cast<int>(sources.size()));
        if (fresh) {
          sources.emplace_back();
          sources.back().albedo =
              scene->materials[static_cast<std::size_t>(d.material)].albedo.cast<double>();
        }
        Source& s = sources[static_cast<std::size_t>(it->second)];
        s.center += area * centroid;
        s.normal += area * normal;
        s.area += area;
        s.triangles.push_back(t);
      }
    }
    SourceGrid grid;
    grid.cell = o.bounce_range_m;
    for (std::size_t i = 0; i < sources.size(); ++i) {
      Source& s = sources[i];
      s.center /= s.area;
      s.normal.normalize();
      grid.cells[grid.CellOf(s.center)].push_back(static_cast<int>(i));
    }
    // Each bounce: sources take the mean irradiance of their triangles' vertices from the light
    // bounced last (the direct light first), then every vertex gathers from them.
    std::vector<Vector3d> last = direct;
    for (int bounce = 0; bounce < o.bounces; ++bounce) {
      for (Source& s : sources) {
        Vector3d sum = Vector3d::Zero();
        double weight = 0;
        for (const std::uint32_t t : s.triangles) {
          for (int k = 0; k < 3; ++k)
            sum += last[scene->indices[t + static_cast<std::uint32_t>(k)]];
          weight += 3;
        }
        s.irradiance = sum / weight;
      }
      std::vector<Vector3d> next(n_vertices);
      for (std::size_t i = 0; i < n_vertices; ++i) {
        const auto [p, n] = lit_point(i);
        next[i] = Gather(sources, grid, occluders, o.shadows, o.bounce_range_m, p, n);
      }
      for (std::size_t i = 0; i < n_vertices; ++i) bounced[i] += next[i];
      last = std::move(next);
    }
  }

  for (std::size_t i = 0; i < n_vertices; ++i) {
    const Vector3d e = Vector3d::Constant(o.ambient) + direct[i] + bounced[i];
    for (int c = 0; c < 3; ++c) scene->vertices[i].irradiance[c] = static_cast<float>(e[c]);
  }
}

}  // namespace corridorsim::render
