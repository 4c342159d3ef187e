// Ceiling lamps (stream worlds.lamps), circular or panels, on or off, and the reflective wall
// panels that mirror circular ones (P3 Fig. 3b/3c). Steps of worlds::Generate
// (generator_internal.h).

#include <algorithm>
#include <cmath>

#include "worlds/generator_internal.h"
#include "worlds/mesh_builder.h"

namespace corridorsim::worlds::generator_internal {

int Builder::AddLamp(const Vector3d& centre, LampShape shape, double radius, const Vector2d& size,
                     int room_door_id) {
  Lamp lamp;
  lamp.id = next_id_++;
  lamp.shape = shape;
  lamp.center = centre;
  lamp.radius_m = shape == LampShape::kCircular ? radius : 0.0;
  lamp.size_m = shape == LampShape::kPanel ? size : Vector2d::Zero();
  lamp.on = !lamps_rng_.Bernoulli(s_.lamps.off_fraction);
  lamp.room_door_id = room_door_id;
  const int material = lamp.on ? mat_.lamp_on : mat_.lamp_off;
  if (shape == LampShape::kCircular) {
    Mesh& mesh = NewMesh(Id("lamp", lamp.id), material, lamp.id, SemanticClass::kLampCircular);
    AddDisc(mesh, centre, radius, -Vector3d::UnitZ(), kDiscSegments);
  } else {
    const AlignedBox2d rect(centre.head<2>() - size / 2, centre.head<2>() + size / 2);
    Mesh& mesh = NewMesh(Id("lamp", lamp.id), material, lamp.id, SemanticClass::kLampPanel);
    AddHorizontalRect(mesh, rect, centre.z(), false, 1.0, rect.min());
  }
  w_.lamps.push_back(lamp);
  return lamp.id;
}

void Builder::PlaceLamps() {
  const LampOptions& l = s_.lamps;
  const double z = s_.height_m - kLampDrop;
  for (std::size_t k = 0; k < w_.segments.size(); ++k) {
    const CorridorSegment& seg = w_.segments[k];
    const double length = (seg.end - seg.start).norm();
    const Vector2d dir = seg.direction();
    for (double s = l.spacing_m / 2; s < length; s += l.spacing_m) {
      const double pos =
          std::clamp(s + lamps_rng_.Uniform(-l.spacing_jitter_m, l.spacing_jitter_m), 0.0, length);
      const Vector2d c = seg.start + pos * dir;
      const bool circular = lamps_rng_.Bernoulli(l.circular_fraction);
      const double radius = lamps_rng_.Uniform(l.radius_min_m, l.radius_max_m);
      const double extent = circular ? radius : l.panel_length_m / 2;
      if (OwnedByEarlierSegment(k, c, extent)) continue;
      Vector2d size(l.panel_length_m, l.panel_width_m);
      if (std::abs(dir.y()) > 0.5) size = Vector2d(l.panel_width_m, l.panel_length_m);
      const Vector2d half = circular ? Vector2d(radius, radius) : Vector2d(size / 2);
      if (!InsideCorridor(AlignedBox2d(c - half, c + half), 0.05)) continue;  // off the walls
      const int id = AddLamp(Vector3d(c.x(), c.y(), z),
                             circular ? LampShape::kCircular : LampShape::kPanel, radius, size, -1);
      lamp_segment_.push_back({id, static_cast<int>(k)});
      AddCeilingKeepout(
          circular ? AlignedBox2d(c - Vector2d(radius, radius), c + Vector2d(radius, radius))
                   : AlignedBox2d(c - size / 2, c + size / 2));
    }
  }
}

void Builder::PlaceReflectors() {
  const LampOptions& l = s_.lamps;
  const double t = s_.wall_thickness_m, H = s_.height_m;
  for (const auto& [lamp_id, segment_index] : lamp_segment_) {
    const Lamp lamp = *std::find_if(w_.lamps.begin(), w_.lamps.end(),
                                    [id = lamp_id](const Lamp& x) { return x.id == id; });
    if (lamp.shape != LampShape::kCircular || !lamp.on) continue;
    if (!lamps_rng_.Bernoulli(l.reflector_fraction)) continue;
    const int side = lamps_rng_.Bernoulli(0.5) ? 1 : -1;
    const int segment_id = w_.segments[segment_index].id;
    for (std::size_t k = 0; k < w_.walls.size(); ++k) {
      const Wall& wall = w_.walls[k];
      if (!wall.side_wall || wall.segment_id != segment_id) continue;
      const Vector2d rel = lamp.center.head<2>() - wall.start;
      const double along = rel.dot(wall.tangent()), dist = rel.dot(wall.inward_normal);
      const Vector2d seg_side(-w_.segments[segment_index].direction().y(),
                              w_.segments[segment_index].direction().x());
      if (wall.inward_normal.dot(seg_side) * side > 0) continue;  // the other wall
      const double s0 = along - l.reflector_length_m / 2, s1 = along + l.reflector_length_m / 2;
      if (dist <= 0 || dist >= s_.width_m || s0 < 0.1 || s1 > wall.length() - 0.1) continue;
      if (!IsFree(static_cast<int>(k), s0 - 0.1, s1 + 0.1)) continue;
      // The mirrored corridor behind the panel must not run into rooms or corridors.
      const double depth = s_.width_m;
      if (OverlapsRoomsOrCorridors(WallRect(wall, s0 - t, s1 + t, 0, -depth - t))) continue;
      room_areas_.push_back(WallRect(wall, s0 - t, s1 + t, 0, -depth - t));
      Reflector r;
      r.id = next_id_++;
      r.wall_id = wall.id;
      r.mirrored_lamp_id = lamp.id;
      const Vector2d face = OnWall(wall, along, 0);
      r.center = Vector3d(face.x(), face.y(), H - l.reflector_height_m / 2);
      r.size_m = Vector2d(l.reflector_length_m, l.reflector_height_m);
      const Vector2d mirrored = lamp.center.head<2>() - 2 * dist * wall.inward_normal;
      r.apparent_lamp_center = Vector3d(mirrored.x(), mirrored.y(), lamp.center.z());
      BuildReflector(r, wall, s0, s1, lamp);
      occupied_[k].push_back({s0 - 0.05, s1 + 0.05});
      reflector_cuts_[k].push_back({s0, s1});
      w_.reflectors.push_back(r);
      break;
    }
  }
}

// The panel is an opening in the top of the wall onto the mirror image of the corridor: a
// mirrored ceiling, the mirrored lamp, and the mirrored far wall (planar mirror by geometry).
void Builder::BuildReflector(const Reflector& r, const Wall& wall, double s0, double s1,
                             const Lamp& lamp) {
  const double t = s_.wall_thickness_m, H = s_.height_m, depth = s_.width_m;
  const double z0 = H - s_.lamps.reflector_height_m;
  const int id = r.id;
  const auto cls = SemanticClass::kReflector;
  AddBox(NewMesh(Id("reflector_far_wall", id), mat_.mirror, id, cls),
         WallBox(wall, s0 - t, s1 + t, z0 - t, H + t, -depth - t, -depth), kWallPeriodM);
  AddBox(NewMesh(Id("reflector_bottom", id), mat_.mirror, id, cls),
         WallBox(wall, s0 - t, s1 + t, z0 - t, z0, -depth - t, -t), kWallPeriodM);
  // The ends stay behind the wall's own faces: an end box reaching the wall plane put its face
  // on the wall band's face beside the panel (coplanar faces of two materials: z-fighting
  // stripes along the panel's ends); the wall band's end faces are the opening's reveals. The
  // top box's underside is the mirrored ceiling (a separate ceiling mesh on the same plane
  // z-fought with it). The boxes run into each other, so their seams cross instead of touching.
  AddBox(NewMesh(Id("reflector_end_a", id), mat_.mirror, id, cls),
         WallBox(wall, s0 - t, s0, z0 - t, H + t, -depth - t, -t), kWallPeriodM);
  AddBox(NewMesh(Id("reflector_end_b", id), mat_.mirror, id, cls),
         WallBox(wall, s1, s1 + t, z0 - t, H + t, -depth - t, -t), kWallPeriodM);
  AddBox(NewMesh(Id("reflector_top", id), mat_.mirror, id, cls),
         WallBox(wall, s0 - t, s1 + t, H, H + t, -depth - t, 0), kWallPeriodM);
  AddDisc(NewMesh(Id("reflector_lamp", id), mat_.lamp_on, id, cls), r.apparent_lamp_center,
          lamp.radius_m, -Vector3d::UnitZ(), kDiscSegments);
}

}  // namespace corridorsim::worlds::generator_internal
