// Distractors (stream worlds.distractors): bookshelves, cabinets, notice boards, posters and
// fire extinguishers on free wall stretches, objects that detectors must reject. A step of
// worlds::Generate (generator_internal.h).

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "worlds/generator_internal.h"
#include "worlds/mesh_builder.h"
#include "worlds/textures.h"

namespace corridorsim::worlds::generator_internal {

// A free stretch of `width` on some side wall, drawn uniformly over all free positions.
std::optional<Builder::Slot> Builder::FindSlot(double width, double margin) {
  struct Gap {
    int wall;
    double lo, slack;
  };
  std::vector<Gap> gaps;
  std::vector<double> weights;
  for (std::size_t k = 0; k < w_.walls.size(); ++k) {
    const Wall& wall = w_.walls[k];
    if (!wall.side_wall) continue;
    auto occ = occupied_[k];
    std::sort(occ.begin(), occ.end(),
              [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
    double s = 0.3;
    occ.push_back({wall.length() - 0.3, wall.length()});
    for (const Interval& iv : occ) {
      const double slack = iv.lo - s - width - 2 * margin;
      if (slack > 0) {
        gaps.push_back({static_cast<int>(k), s + margin, slack});
        weights.push_back(slack);
      }
      s = std::max(s, iv.hi);
    }
  }
  if (gaps.empty()) return std::nullopt;
  const Gap& g = gaps[distractors_rng_.Categorical(weights)];
  return Slot{g.wall, g.lo + distractors_rng_.Uniform(0, g.slack)};
}

void Builder::PlaceDistractors() {
  const DistractorOptions& x = s_.distractors;
  // Appearance randomisation keeps a fraction of each count (1 without it).
  const auto kept = [&](int count) {
    return static_cast<int>(std::lround(count * w_.appearance.distractor_density));
  };
  const DistractorKind kinds[] = {
      {"distractors.bookshelves", SemanticClass::kBookshelf, kept(x.bookshelves)},
      {"distractors.cabinets", SemanticClass::kCabinet, kept(x.cabinets)},
      {"distractors.notice_boards", SemanticClass::kNoticeBoard, kept(x.notice_boards)},
      {"distractors.posters", SemanticClass::kPoster, kept(x.posters)},
      {"distractors.fire_extinguishers", SemanticClass::kFireExtinguisher,
       kept(x.fire_extinguishers)},
  };
  for (const DistractorKind& kind : kinds) {
    for (int n = 0; n < kind.count; ++n) PlaceDistractor(kind, n);
  }
}

void Builder::PlaceDistractor(const DistractorKind& kind, int n) {
  auto& rng = distractors_rng_;
  Vector3d size;  // along the wall, out of the wall, height
  double z0 = 0.0;
  switch (kind.cls) {
    case SemanticClass::kBookshelf:
      size = {rng.Uniform(0.8, 1.0), 0.35, rng.Uniform(1.8, 2.0)};
      break;
    case SemanticClass::kCabinet:
      size = {rng.Uniform(0.8, 1.0), 0.45, rng.Uniform(1.0, 1.9)};
      break;
    case SemanticClass::kNoticeBoard:
      size = {1.2, 0.03, 0.9};
      z0 = 1.0;
      break;
    case SemanticClass::kPoster: {
      const double w = rng.Uniform(0.45, 0.65);
      size = {w, 0.004, w * 1.414};
      z0 = 1.6 - size.z() / 2;
      break;
    }
    default:
      size = {0.18, 0.18, 0.55};
      z0 = 0.15;
      break;  // fire extinguisher
  }
  const auto slot = FindSlot(size.x(), 0.15);
  if (!slot) {
    throw OptionsError({kind.key, "only " + std::to_string(n) + " of " +
                                      std::to_string(kind.count) +
                                      " fit on the free wall stretches of this world"});
  }
  const Wall& wall = w_.walls[slot->wall];
  const double s0 = slot->s0, s1 = s0 + size.x();
  occupied_[slot->wall].push_back({s0 - 0.05, s1 + 0.05});
  Distractor d;
  d.id = next_id_++;
  d.semantic_class = kind.cls;
  d.wall_id = wall.id;
  const AlignedBox3d box = WallBox(wall, s0, s1, z0, z0 + size.z(), 0, size.y());
  d.center = box.center();
  d.size_m = size;
  d.normal = Vector3d(wall.inward_normal.x(), wall.inward_normal.y(), 0);
  const Vector3d front = d.center + d.normal * (size.y() / 2 + kSurfaceOffset);
  const std::string name = Id(SemanticClassName(kind.cls).c_str(), d.id);
  const int tex_w = 256, tex_h = int(256 * size.z() / size.x());
  switch (kind.cls) {
    case SemanticClass::kBookshelf:
    case SemanticClass::kCabinet: {
      const bool shelf = kind.cls == SemanticClass::kBookshelf;
      Solid(name, shelf ? mat_.furniture : mat_.metal, d.id, kind.cls, box);
      const Image8 image = shelf ? MakeBookshelfTexture(textures_rng_, tex_w, tex_h)
                                 : MakeCabinetTexture(textures_rng_, tex_w, tex_h);
      const int mat = TexturedMaterial(name, AddTexture(name, image));
      AddDecal(name + "_front", mat, d.id, kind.cls, front, d.normal, size.x(), size.z());
      break;
    }
    case SemanticClass::kNoticeBoard:
    case SemanticClass::kPoster: {
      d.text = std::to_string(rng.UniformInt(1, 9999));
      AddBox(NewMesh(name, mat_.frame, d.id, kind.cls), box, 1.0);
      const Image8 image = kind.cls == SemanticClass::kPoster
                               ? MakePosterTexture(textures_rng_, d.text, tex_w, tex_h)
                               : MakeNoticeBoardTexture(textures_rng_, d.text, tex_w, tex_h);
      const int mat = TexturedMaterial(name, AddTexture(name, image));
      AddDecal(name + "_front", mat, d.id, kind.cls, front, d.normal, size.x(), size.z());
      break;
    }
    default:
      Solid(name, mat_.extinguisher, d.id, kind.cls, box);
      break;
  }
  w_.distractors.push_back(d);
}

}  // namespace corridorsim::worlds::generator_internal
