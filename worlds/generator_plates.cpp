// Door plates (stream worlds.plates): which doors get one, their size, side, colours and
// texture with the room number. A step of worlds::Generate (generator_internal.h).

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "worlds/generator_internal.h"
#include "worlds/mesh_builder.h"
#include "worlds/textures.h"

namespace corridorsim::worlds::generator_internal {

// A plate colour and a text colour (RGB, 0-255) whose luminances differ by at least 100:
// both uniform, the text drawn again up to 64 times, then black or white, whichever differs
// more.
std::array<Vector3d, 2> Builder::PlateColours(RandomStream& rng) {
  const auto luma = [](const Vector3d& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; };
  const auto draw = [&] {
    // One draw per statement: the order of a call's arguments is the compiler's (docs/worlds.md).
    const double b = rng.Uniform(0, 255), g = rng.Uniform(0, 255), r = rng.Uniform(0, 255);
    return Vector3d(r, g, b);
  };
  const Vector3d plate = draw();
  for (int k = 0; k < 64; ++k) {
    const Vector3d text = draw();
    if (std::abs(luma(plate) - luma(text)) >= 100) return {plate, text};
  }
  return {plate, luma(plate) > 127.5 ? Vector3d::Zero() : Vector3d::Constant(255)};
}

void Builder::PlacePlates() {
  const PlateOptions& p = s_.plates;
  std::vector<std::size_t> order(w_.doors.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  plates_rng_.Shuffle(order);
  order.resize(static_cast<std::size_t>(p.count));
  std::sort(order.begin(), order.end());
  for (const std::size_t i : order) {
    const Doorway& door = w_.doors[i];
    const int wall_index = door_walls_[i];
    const Wall& wall = w_.walls[wall_index];
    const double scale = 1.0 + plates_rng_.Uniform(-p.size_jitter, p.size_jitter);
    const double width = p.width_m * scale, height = p.height_m * scale;
    const bool before = plates_rng_.Bernoulli(0.5);  // beside column a, or beside column b
    const double s_centre =
        before ? door_starts_[i] - p.gap_from_frame_m - width / 2
               : door_starts_[i] + plan_.door_footprint_m + p.gap_from_frame_m + width / 2;
    DoorPlate plate;
    plate.id = next_id_++;
    plate.door_id = door.id;
    plate.room_number = door.room_number;
    const double depth = 0.006;
    const Vector2d c = OnWall(wall, s_centre, depth + kSurfaceOffset);
    // Appearance randomisation: each plate's own stream, so the plates do not shift each other.
    RandomStream look(w_.seed, static_cast<std::uint64_t>(plate.id), "worlds.appearance.plate");
    const double jitter = s_.appearance.plate_height_jitter_m;
    plate.center = Vector3d(c.x(), c.y(), p.center_height_m + look.Uniform(-jitter, jitter));
    std::optional<std::array<Vector3d, 2>> colours;
    const std::array<Vector3d, 2> drawn = PlateColours(look);
    if (s_.appearance.plate_colours) colours = drawn;
    plate.normal = Vector3d(wall.inward_normal.x(), wall.inward_normal.y(), 0);
    plate.size_m = Vector2d(width, height);
    PlateStyle style;  // recorded in the ground truth for detector developers
    plate.texture = AddTexture(
        Id("plate", plate.id),
        MakePlateTexture(textures_rng_, plate.room_number, width / height, &style, colours));
    plate.font = style.font;
    plate.border_px = style.border_px;
    // Texture px -> face metres: the decal maps texture x to right, row 0 to the top.
    if (style.width_px > 0 && style.height_px > 0) {
      const auto face = [&](int x_px, int y_px) {
        return Vector2d((double(x_px) / style.width_px - 0.5) * width,
                        (0.5 - double(y_px) / style.height_px) * height);
      };
      const Vector2d a = face(style.number_x0_px, style.number_y1_px);
      const Vector2d b = face(style.number_x1_px, style.number_y0_px);
      plate.number_min_in_face = a.cwiseMin(b);
      plate.number_max_in_face = a.cwiseMax(b);
    }
    const int material = TexturedMaterial(Id("plate", plate.id), plate.texture);
    const int backing = PlainMaterial(Id("plate_backing", plate.id), {0.3f, 0.3f, 0.3f});
    const double z0 = p.center_height_m - height / 2, z1 = p.center_height_m + height / 2;
    AddBox(NewMesh(Id("plate_backing", plate.id), backing, plate.id, SemanticClass::kDoorPlate),
           WallBox(wall, s_centre - width / 2, s_centre + width / 2, z0, z1, 0, depth), 1.0);
    AddDecal(Id("plate", plate.id), material, plate.id, SemanticClass::kDoorPlate, plate.center,
             plate.normal, width, height);
    occupied_[wall_index].push_back({s_centre - width / 2 - 0.05, s_centre + width / 2 + 0.05});
    w_.plates.push_back(plate);
  }
}

}  // namespace corridorsim::worlds::generator_internal
