// The corridor's shell, as the floor plan (PlanLayout) lays it out: the walls with their door
// openings and reflective panels cut out, the floor cells and the ceiling over them, tiled or
// in plain stretches (stream worlds.ceiling.plain); and where a point lies in the corridor.
// Steps of worlds::Generate (generator_internal.h).

#include <algorithm>
#include <cmath>
#include <string>

#include "worlds/generator_internal.h"
#include "worlds/mesh_builder.h"

namespace corridorsim::worlds::generator_internal {

// Whether point p of segment k lies in the part of the corridor owned by an earlier segment
// (corner squares, the T's junction).
bool Builder::OwnedByEarlierSegment(std::size_t k, const Vector2d& p, double margin) const {
  for (std::size_t j = 0; j < k; ++j) {
    if (Inflated(plan_.segment_rects[j], margin).contains(p)) return true;
  }
  return false;
}

// Whether `box` lies in the walkable area, at least `margin` from every wall.
bool Builder::InsideCorridor(const AlignedBox2d& box, double margin) const {
  const AlignedBox2d grown = Inflated(box, margin);
  for (const Vector2d& corner :
       {grown.min(), grown.max(), Vector2d(grown.min().x(), grown.max().y()),
        Vector2d(grown.max().x(), grown.min().y())}) {
    if (std::none_of(plan_.segment_rects.begin(), plan_.segment_rects.end(),
                     [&](const AlignedBox2d& r) { return r.contains(corner); })) {
      return false;
    }
  }
  return true;
}

void Builder::BuildWalls() {
  const double t = s_.wall_thickness_m, H = s_.height_m;
  for (std::size_t k = 0; k < w_.walls.size(); ++k) {
    const Wall& wall = w_.walls[k];
    auto cuts = door_cuts_[k];
    std::sort(cuts.begin(), cuts.end(),
              [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
    double s = 0.0;
    int piece = 0;
    cuts.push_back({wall.length(), wall.length()});
    for (const Interval& cut : cuts) {
      if (cut.lo - s > 1e-9) BuildWallPiece(wall, static_cast<int>(k), s, cut.lo, piece++, t, H);
      s = cut.hi;
    }
    // Outer corners: the square behind both wall faces where two walls meet is filled, so no
    // seam between the two wall boxes can show the void behind them. Inner corners (L, T)
    // would put the square into the corridor and are left alone.
    for (const double s0 : {-t, wall.length()}) {
      const AlignedBox2d square = WallRect(wall, s0, s0 + t, 0, -t);
      const bool in_corridor =
          std::any_of(plan_.segment_rects.begin(), plan_.segment_rects.end(),
                      [&](const AlignedBox2d& r) { return Overlaps(square, r); });
      if (in_corridor) continue;
      Solid(Id("wall_corner", wall.id) + (s0 < 0 ? "_start" : "_end"), mat_.wall, wall.id,
            SemanticClass::kWall, WallBox(wall, s0, s0 + t, -kSeam, H + kSeam, -t, 0));
    }
  }
}

// A solid stretch of wall [s0, s1]; reflective panels cut its top band.
void Builder::BuildWallPiece(const Wall& wall, int k, double s0, double s1, int piece, double t,
                             double H) {
  const std::string name = Id("wall", wall.id) + "_" + std::to_string(piece);
  Collide(WallBox(wall, s0, s1, 0, H, -t, 0), wall.id, SemanticClass::kWall);
  Mesh& mesh = NewMesh(name, mat_.wall, wall.id, SemanticClass::kWall);
  std::vector<Interval> bands;
  for (const Interval& r : reflector_cuts_[k]) {
    if (r.lo >= s0 && r.hi <= s1) bands.push_back(r);
  }
  if (bands.empty()) {
    AddBox(mesh, WallBox(wall, s0, s1, -kSeam, H + kSeam, -t, 0), kWallPeriodM);
    return;
  }
  const double z_band = H - s_.lamps.reflector_height_m;
  AddBox(mesh, WallBox(wall, s0, s1, -kSeam, z_band, -t, 0), kWallPeriodM);
  std::sort(bands.begin(), bands.end(),
            [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
  double s = s0;
  bands.push_back({s1, s1});
  for (const Interval& band : bands) {
    if (band.lo - s > 1e-9)
      AddBox(mesh, WallBox(wall, s, band.lo, z_band, H + kSeam, -t, 0), kWallPeriodM);
    s = band.hi;
  }
}

void Builder::BuildFloorAndCeiling() {
  const double tile = s_.ceiling.tile_size_m;
  const double offset_y = ceiling_rng_.Uniform(0, tile), offset_x = ceiling_rng_.Uniform(0, tile);
  tile_offset_ = Vector2d(offset_x, offset_y);
  for (std::size_t i = 0; i < plan_.floor_cells.size(); ++i) {
    const AlignedBox2d& cell = plan_.floor_cells[i];
    const int floor_id = next_id_++;
    AddHorizontalRect(NewMesh(Id("floor", floor_id), mat_.floor, floor_id, SemanticClass::kFloor),
                      cell, 0.0, true, kFloorPeriodM);
    for (const auto& [rect, plain] : CeilingStretches(cell)) {
      const int ceiling_id = next_id_++;
      Mesh& mesh = NewMesh(Id("ceiling", ceiling_id), plain ? mat_.room_ceiling : mat_.ceiling,
                           ceiling_id, SemanticClass::kCeiling);
      if (plain) {
        AddHorizontalRect(mesh, rect, s_.height_m, false, kWallPeriodM);
        const std::size_t index = plain_ceiling_.size();
        plain_ceiling_.push_back(rect);
        ForKeepoutCells(
            rect, [&](const std::pair<long, long>& grid) { plain_cells_[grid].push_back(index); });
      } else {
        AddHorizontalRect(mesh, rect, s_.height_m, false, tile * kCeilingTilesPerTexture,
                          tile_offset_);
      }
    }
  }
}

// The cell's ceiling cut along its longer side into stretches of about plain_stretch_m, each
// plain (plastered like the rooms', no tiles) with chance plain_fraction, neighbours of one
// kind merged. Without plain stretches the cell is one tiled stretch and nothing is drawn, so
// such worlds are the ones generated before this option existed.
std::vector<std::pair<AlignedBox2d, bool>> Builder::CeilingStretches(const AlignedBox2d& cell) {
  const CeilingOptions& c = s_.ceiling;
  if (c.plain_fraction <= 0) return {{cell, false}};
  const int axis = cell.sizes().x() >= cell.sizes().y() ? 0 : 1;
  const double length = cell.sizes()[axis];
  // Bounded: the corridor's length (world bounds) over plain_stretch_m >= 0.5 m.
  const int n = std::max(1, static_cast<int>(std::lround(length / c.plain_stretch_m)));
  std::vector<std::pair<AlignedBox2d, bool>> out;
  for (int k = 0; k < n; ++k) {
    const bool plain = plain_rng_.Uniform(0, 1) < c.plain_fraction;
    AlignedBox2d part = cell;
    part.min()[axis] = cell.min()[axis] + length * k / n;
    part.max()[axis] = k + 1 == n ? cell.max()[axis] : cell.min()[axis] + length * (k + 1) / n;
    if (!out.empty() && out.back().second == plain) {
      out.back().first.max()[axis] = part.max()[axis];
    } else {
      out.emplace_back(part, plain);
    }
  }
  return out;
}

// Whether p lies on a plain stretch or within `margin` of one: only the stretches filed under
// the grid cells around p are tested (a corridor has up to thousands of stretches and a
// million tile corners).
bool Builder::OnPlainCeiling(const Vector2d& p, double margin) const {
  if (plain_ceiling_.empty()) return false;
  bool on = false;
  const AlignedBox2d around(p - Vector2d(margin, margin), p + Vector2d(margin, margin));
  ForKeepoutCells(around, [&](const std::pair<long, long>& grid) {
    const auto it = plain_cells_.find(grid);
    if (it == plain_cells_.end()) return;
    for (const std::size_t i : it->second) {
      on = on || Inflated(plain_ceiling_[i], margin).contains(p);
    }
  });
  return on;
}

bool Builder::NearWall(const Vector2d& p, double margin) const {
  for (const Wall& w : w_.walls) {
    const Vector2d rel = p - w.start;
    const double along = rel.dot(w.tangent()), across = rel.dot(w.inward_normal);
    if (along > -margin && along < w.length() + margin && std::abs(across) < margin) return true;
  }
  return false;
}

}  // namespace corridorsim::worlds::generator_internal
