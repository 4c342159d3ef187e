// Ceiling fixtures (stream worlds.ceiling): vents, sprinklers and smoke detectors clear of the
// lamps, and the corner points P3 uses (their corners, visible tile-seam crossings). A step of
// worlds::Generate (generator_internal.h).

#include <algorithm>
#include <cmath>
#include <string>

#include "worlds/generator_internal.h"
#include "worlds/mesh_builder.h"

namespace corridorsim::worlds::generator_internal {

bool Builder::CeilingFree(const AlignedBox2d& box) const {
  // Only the keepouts filed under the cells the box touches can overlap it (an overlap shares
  // an inner point, which lies in a cell both are filed under).
  const AlignedBox2d query = Inflated(box, 0.05);
  bool free = true;
  ForKeepoutCells(query, [&](const std::pair<long, long>& cell) {
    const auto it = keepout_cells_.find(cell);
    if (it == keepout_cells_.end()) return;
    for (const std::size_t i : it->second) free = free && !Overlaps(query, ceiling_keepout_[i]);
  });
  return free;
}

void Builder::AddCeilingKeepout(const AlignedBox2d& box) {
  const std::size_t index = ceiling_keepout_.size();
  ceiling_keepout_.push_back(box);
  ForKeepoutCells(
      box, [&](const std::pair<long, long>& cell) { keepout_cells_[cell].push_back(index); });
}

void Builder::AddCorner(CornerKind kind, const Vector3d& p) {
  w_.corner_points.push_back(CornerPoint{next_id_++, kind, p});
}

void Builder::PlaceCeilingFixtures() {
  const CeilingOptions& c = s_.ceiling;
  const LampOptions& l = s_.lamps;
  const double H = s_.height_m;
  const double lamp_extent = std::max(l.radius_max_m, l.panel_width_m / 2);
  const double vent_lane = lamp_extent + 0.1 + c.vent_size_m / 2;  // right of the axis
  const double sprinkler_lane = lamp_extent + 0.25;                // left of the axis
  for (std::size_t k = 0; k < w_.segments.size(); ++k) {
    const CorridorSegment& seg = w_.segments[k];
    const double length = (seg.end - seg.start).norm();
    const Vector2d dir = seg.direction(), left(-dir.y(), dir.x());
    auto along = [&](double spacing, auto&& place) {
      for (double s = ceiling_rng_.Uniform(0.3, 0.7) * spacing; s < length - 0.3; s += spacing)
        place(s);
    };
    along(c.vent_spacing_m, [&](double s) {
      const Vector2d p = seg.start + s * dir - vent_lane * left;
      const double h = c.vent_size_m / 2;
      const AlignedBox2d box(p - Vector2d(h, h), p + Vector2d(h, h));
      if (OwnedByEarlierSegment(k, p, h) || !CeilingFree(box)) return;
      AddCeilingKeepout(box);
      const int id = next_id_++;
      AddHorizontalRect(NewMesh(Id("vent", id), mat_.vent, id, SemanticClass::kVent), box,
                        H - 0.004, false, c.vent_size_m, box.min());
      for (const Vector2d& q : {box.min(), Vector2d(box.max().x(), box.min().y()), box.max(),
                                Vector2d(box.min().x(), box.max().y())}) {
        AddCorner(CornerKind::kVent, Vector3d(q.x(), q.y(), H - 0.004));
      }
    });
    along(c.sprinkler_spacing_m, [&](double s) {
      const Vector2d p = seg.start + s * dir + sprinkler_lane * left;
      AddRoundFixture(k, p, 0.025, H - 0.01, mat_.sprinkler, SemanticClass::kSprinkler,
                      CornerKind::kSprinkler);
    });
    along(c.smoke_detector_spacing_m, [&](double s) {
      const Vector2d p = seg.start + s * dir - sprinkler_lane * left;
      AddRoundFixture(k, p, 0.06, H - 0.03, mat_.detector, SemanticClass::kSmokeDetector,
                      CornerKind::kSmokeDetector);
    });
  }
  AddTileSeamCorners();
}

void Builder::AddRoundFixture(std::size_t k, const Vector2d& p, double r, double z, int material,
                              SemanticClass cls, CornerKind kind) {
  const AlignedBox2d box(p - Vector2d(r, r), p + Vector2d(r, r));
  if (OwnedByEarlierSegment(k, p, r) || !CeilingFree(box)) return;
  AddCeilingKeepout(box);
  const int id = next_id_++;
  const std::string name = cls == SemanticClass::kSprinkler ? "sprinkler" : "smoke_detector";
  AddDisc(NewMesh(Id(name.c_str(), id), material, id, cls), Vector3d(p.x(), p.y(), z), r,
          -Vector3d::UnitZ(), 16);
  AddCorner(kind, Vector3d(p.x(), p.y(), z));
}

// Crossings of the ceiling tile seams that are visible: away from walls and fixtures.
void Builder::AddTileSeamCorners() {
  const double tile = s_.ceiling.tile_size_m, margin = 0.05;
  for (const AlignedBox2d& cell : plan_.floor_cells) {
    const auto first = [&](double lo, double offset) {
      return static_cast<long>(std::ceil((lo - offset) / tile - 1e-9));
    };
    for (long i = first(cell.min().x(), tile_offset_.x());; ++i) {
      const double x = tile_offset_.x() + double(i) * tile;
      if (x >= cell.max().x() - 1e-9) break;
      for (long j = first(cell.min().y(), tile_offset_.y());; ++j) {
        const double y = tile_offset_.y() + double(j) * tile;
        if (y >= cell.max().y() - 1e-9) break;
        const Vector2d p(x, y);
        if (NearWall(p, margin) || OnPlainCeiling(p, margin)) continue;
        const AlignedBox2d dot(p - Vector2d(0.01, 0.01), p + Vector2d(0.01, 0.01));
        if (!CeilingFree(dot)) continue;
        AddCorner(CornerKind::kTileSeam, Vector3d(x, y, s_.height_m));
      }
    }
  }
}

}  // namespace corridorsim::worlds::generator_internal
