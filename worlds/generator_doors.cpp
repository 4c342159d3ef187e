// Doorways (stream worlds.doors), spaced along each wall as many as the plan (PlanLayout) gave
// it: closed, open or empty, with frame and leaf, and the room behind an open or empty one; then
// the room numbers (stream worlds.plates). A step of worlds::Generate (generator_internal.h).

#include <algorithm>
#include <cmath>
#include <string>

#include "worlds/generator_internal.h"
#include "worlds/mesh_builder.h"

namespace corridorsim::worlds::generator_internal {

void Builder::PlaceDoors() {
  const DoorOptions& d = s_.doors;
  const double f = plan_.door_footprint_m, g = d.min_gap_m, t = s_.wall_thickness_m;
  const double weights[] = {d.closed_weight, d.open_weight, d.empty_weight};
  const DoorState states[] = {DoorState::kClosed, DoorState::kOpen, DoorState::kEmpty};
  for (std::size_t k = 0; k < w_.walls.size(); ++k) {
    const int n = plan_.doors_per_wall[k];
    if (n == 0) continue;
    const Wall& wall = w_.walls[k];
    // Stick breaking: the slack beyond minimum spacing is split at n sorted uniform points.
    const double slack = UsableWallLength(wall, s_) - n * f - (n - 1) * g;
    std::vector<double> cuts(n);
    for (double& c : cuts) c = doors_rng_.Uniform(0, std::max(0.0, slack));
    std::sort(cuts.begin(), cuts.end());
    for (int i = 0; i < n; ++i) {
      const double start = g + i * (f + g) + cuts[i];
      Doorway door;
      door.id = next_id_++;
      door.wall_id = wall.id;
      door.state = states[doors_rng_.Categorical(weights)];
      door.column_a = OnWall(wall, start + d.frame_width_m / 2, 0);
      door.column_b = OnWall(wall, start + f - d.frame_width_m / 2, 0);
      door.inward_normal = wall.inward_normal;
      door.width_m = d.width_m;
      door.top_height_m = d.height_m;
      door.column_width_m = d.frame_width_m;
      if (door.state != DoorState::kClosed) {
        // The room is room_width_m wide, narrowed where needed to stop half-way to the
        // neighbouring doorways on this wall (less its wall), so that rooms of close doors
        // share a wall instead of turning each other's doors into closed ones.
        const double centre = start + f / 2;
        const double half = std::max(d.room_width_m, f + 0.4) / 2;
        double lo = centre - half, hi = centre + half;
        if (i > 0) lo = std::max(lo, (g + (i - 1) * (f + g) + cuts[i - 1] + f + start) / 2 + t);
        if (i + 1 < n) hi = std::min(hi, (start + f + g + (i + 1) * (f + g) + cuts[i + 1]) / 2 - t);
        const AlignedBox2d area = WallRect(wall, lo, hi, -t, -t - d.room_depth_m);
        if (OverlapsRoomsOrCorridors(Inflated(area, t))) {
          door.state = DoorState::kClosed;  // no space behind this wall for a room
        } else {
          door.room = Room{area, d.room_height_m};
          room_areas_.push_back(Inflated(area, t));
        }
      }
      occupied_[k].push_back({start - 0.05, start + f + 0.05});
      door_cuts_[k].push_back({start, start + f});
      door_walls_.push_back(static_cast<int>(k));
      door_starts_.push_back(start);
      w_.doors.push_back(door);
    }
  }
  // Room numbers run along the walls with occasional skipped numbers, so they are unique.
  int floor = s_.plates.first_floor;
  if (floor == 0) floor = static_cast<int>(plates_rng_.UniformInt(1, 9));
  int number = floor * 100;
  for (Doorway& door : w_.doors) {
    number += static_cast<int>(plates_rng_.UniformInt(1, 2));
    door.room_number = std::to_string(number);
  }
  for (std::size_t i = 0; i < w_.doors.size(); ++i) BuildDoor(i);
}

void Builder::BuildDoor(std::size_t index) {
  const Doorway& door = w_.doors[index];
  const Wall& wall = w_.walls[door_walls_[index]];
  const DoorOptions& d = s_.doors;
  const double start = door_starts_[index], f = plan_.door_footprint_m;
  const double t = s_.wall_thickness_m, p = d.frame_protrusion_m, fw = d.frame_width_m;
  const double bar_top = d.height_m + d.bar_height_m;
  const int id = door.id;
  // Columns and top bar: the door feature of P2/P3.
  Solid(Id("door_column_a", id), mat_.frame, id, SemanticClass::kDoorFrame,
        WallBox(wall, start, start + fw, -kSeam, bar_top, -t - p, p));
  Solid(Id("door_column_b", id), mat_.frame, id, SemanticClass::kDoorFrame,
        WallBox(wall, start + f - fw, start + f, -kSeam, bar_top, -t - p, p));
  Solid(Id("door_bar", id), mat_.frame, id, SemanticClass::kDoorFrame,
        WallBox(wall, start + fw, start + f - fw, d.height_m, bar_top, -t - p, p));
  Solid(Id("door_header", id), mat_.wall, wall.id, SemanticClass::kWall,
        WallBox(wall, start, start + f, bar_top, s_.height_m + kSeam, -t, 0));
  if (door.state == DoorState::kClosed) {
    Solid(
        Id("door_leaf", id), mat_.door_leaf, id, SemanticClass::kDoorLeaf,
        WallBox(wall, start + fw, start + f - fw, -kSeam, d.height_m, -t / 2 - 0.02, -t / 2 + 0.02),
        d.height_m);
  } else if (door.state == DoorState::kOpen) {
    // The leaf swung by 90 degrees into the room, hinged at column a.
    Solid(
        Id("door_leaf", id), mat_.door_leaf, id, SemanticClass::kDoorLeaf,
        WallBox(wall, start + fw, start + fw + 0.04, -kSeam, d.height_m - 0.01, -t - d.width_m, -t),
        d.height_m);
  }
  if (door.room) BuildRoom(door, wall);
}

void Builder::BuildRoom(const Doorway& door, const Wall& wall) {
  const Room& room = *door.room;
  const double t = s_.wall_thickness_m, h = room.ceiling_height_m;
  const int id = door.id;
  // The room's floor runs under the doorway's threshold up to the corridor's floor.
  AlignedBox2d floor_area = room.footprint;
  floor_area.extend(
      room.footprint.center() +
      wall.inward_normal *
          (room.footprint.sizes().dot(wall.inward_normal.cwiseAbs()) / 2 + s_.wall_thickness_m));
  Mesh& floor = NewMesh(Id("room_floor", id), mat_.room_floor, id, SemanticClass::kRoom);
  AddHorizontalRect(floor, floor_area, 0.0, true, kFloorPeriodM);
  // A strip kSeam either side of the edge, 0.5 mm below: the two floors meet edge to edge in
  // one plane, with T-junctions between their patches that can open one-pixel holes onto the
  // void; a ray through such a hole meets the strip (hidden everywhere else).
  const Vector2d edge =
      floor_area.center() + wall.inward_normal.cwiseProduct(floor_area.sizes() / 2);
  AlignedBox2d strip = floor_area;
  for (int a = 0; a < 2; ++a) {
    if (std::abs(wall.inward_normal[a]) < 0.5) continue;
    strip.min()[a] = edge[a] - kSeam;
    strip.max()[a] = edge[a] + kSeam;
  }
  AddHorizontalRect(floor, strip, -0.0005, true, kFloorPeriodM);
  Mesh& ceiling = NewMesh(Id("room_ceiling", id), mat_.room_ceiling, id, SemanticClass::kRoom);
  AddHorizontalRect(ceiling, room.footprint, h, false, kWallPeriodM);
  // Three walls; the fourth is the back of the corridor wall.
  const AlignedBox2d outer = Inflated(room.footprint, t);
  const Vector2d n = wall.inward_normal;
  const Vector2d lo = outer.min(), hi = outer.max(), ilo = room.footprint.min(),
                 ihi = room.footprint.max();
  std::vector<AlignedBox2d> sides;
  if (std::abs(n.x()) > 0.5) {  // wall runs along y; the room extends along -n.x
    sides.emplace_back(Vector2d(lo.x(), lo.y()), Vector2d(hi.x(), ilo.y()));
    sides.emplace_back(Vector2d(lo.x(), ihi.y()), Vector2d(hi.x(), hi.y()));
    sides.push_back(n.x() > 0
                        ? AlignedBox2d(Vector2d(lo.x(), ilo.y()), Vector2d(ilo.x(), ihi.y()))
                        : AlignedBox2d(Vector2d(ihi.x(), ilo.y()), Vector2d(hi.x(), ihi.y())));
  } else {
    sides.emplace_back(Vector2d(lo.x(), lo.y()), Vector2d(ilo.x(), hi.y()));
    sides.emplace_back(Vector2d(ihi.x(), lo.y()), Vector2d(hi.x(), hi.y()));
    sides.push_back(n.y() > 0
                        ? AlignedBox2d(Vector2d(ilo.x(), lo.y()), Vector2d(ihi.x(), ilo.y()))
                        : AlignedBox2d(Vector2d(ilo.x(), ihi.y()), Vector2d(ihi.x(), hi.y())));
  }
  for (std::size_t k = 0; k < sides.size(); ++k) {
    const AlignedBox3d box(Vector3d(sides[k].min().x(), sides[k].min().y(), -kSeam),
                           Vector3d(sides[k].max().x(), sides[k].max().y(), h + kSeam));
    Solid(Id("room_wall", id) + "_" + std::to_string(k), mat_.room_wall, id, SemanticClass::kRoom,
          box);
  }
  if (s_.lamps.room_lamps) {
    const Vector2d c = room.footprint.center();
    const double r = (s_.lamps.radius_min_m + s_.lamps.radius_max_m) / 2;
    AddLamp(Vector3d(c.x(), c.y(), h - kLampDrop), LampShape::kCircular, r, {0, 0}, door.id);
  }
}

}  // namespace corridorsim::worlds::generator_internal
