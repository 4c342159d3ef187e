#include "worlds/ground_truth_reader.h"

#include <climits>
#include <initializer_list>

#include "common/io/json_input.h"

namespace corridorsim::worlds {
namespace {

using Json = nlohmann::ordered_json;

int Id(const JsonField& f) {
  const std::int64_t v = f.Integer();
  if (v < INT_MIN || v > INT_MAX) f.Fail("out of range for an id");
  return static_cast<int>(v);
}

Eigen::Vector3d Vec3(const JsonField& f) {
  const auto v = f.Numbers<3>();
  return {v[0], v[1], v[2]};
}

Eigen::Vector2d Vec2(const JsonField& f) {
  const auto v = f.Numbers<2>();
  return {v[0], v[1]};
}

// An enum from its name, one of `values` as `name_of` writes them.
template <typename E, typename NameOf>
E EnumOf(const JsonField& f, std::initializer_list<E> values, NameOf name_of) {
  const std::string text = f.String();
  std::string known;
  for (const E value : values) {
    if (name_of(value) == text) return value;
    known += (known.empty() ? "" : ", ") + name_of(value);
  }
  f.Fail("unknown value (expected one of " + known + ")");
}

// Calls each(element) for every element of the array at `key`.
template <typename Each>
void ForEach(const JsonField& top, const char* key, Each each) {
  const JsonField array = top.At(key);
  const std::size_t n = array.ArraySize();
  for (std::size_t i = 0; i < n; ++i) each(array.At(i));
}

}  // namespace

World ParseGroundTruthJson(std::string_view text, const std::string& file) {
  const Json document = ParseJsonInput(text, file);
  const JsonField top{file, "", document};
  World world;
  world.seed = top.At("seed").Unsigned();
  ForEach(top, "door_plates", [&](const JsonField& p) {
    DoorPlate plate;
    plate.id = Id(p.At("id"));
    plate.door_id = Id(p.At("door_id"));
    plate.room_number = p.At("room_number").String();
    plate.center = Vec3(p.At("center"));
    plate.normal = Vec3(p.At("normal"));
    plate.size_m = Vec2(p.At("size"));
    world.plates.push_back(std::move(plate));
  });
  ForEach(top, "lamps", [&](const JsonField& l) {
    Lamp lamp;
    lamp.id = Id(l.At("id"));
    lamp.shape = EnumOf(l.At("shape"), {LampShape::kCircular, LampShape::kPanel}, LampShapeName);
    lamp.center = Vec3(l.At("center"));
    if (lamp.shape == LampShape::kCircular) {
      lamp.radius_m = l.At("radius").Number();
    } else {
      lamp.size_m = Vec2(l.At("size"));
    }
    lamp.on = l.At("on").Bool();
    if (l.Has("room_door_id")) lamp.room_door_id = Id(l.At("room_door_id"));
    world.lamps.push_back(lamp);
  });
  ForEach(top, "doors", [&](const JsonField& d) {
    Doorway door;
    door.id = Id(d.At("id"));
    door.state = EnumOf(d.At("state"), {DoorState::kClosed, DoorState::kOpen, DoorState::kEmpty},
                        DoorStateName);
    door.wall_id = Id(d.At("wall_id"));
    door.column_a = Vec2(d.At("column_a"));
    door.column_b = Vec2(d.At("column_b"));
    door.top_height_m = d.At("top_height").Number();
    door.width_m = d.At("width").Number();
    door.column_width_m = d.At("column_width").Number();
    door.inward_normal = Vec2(d.At("inward_normal"));
    door.room_number = d.At("room_number").String();
    world.doors.push_back(std::move(door));
  });
  ForEach(top, "reflectors", [&](const JsonField& r) {
    Reflector reflector;
    reflector.id = Id(r.At("id"));
    reflector.wall_id = Id(r.At("wall_id"));
    reflector.mirrored_lamp_id = Id(r.At("mirrored_lamp_id"));
    reflector.center = Vec3(r.At("center"));
    reflector.size_m = Vec2(r.At("size"));
    reflector.apparent_lamp_center = Vec3(r.At("apparent_lamp_center"));
    world.reflectors.push_back(reflector);
  });
  ForEach(top, "corner_points", [&](const JsonField& c) {
    CornerPoint corner;
    corner.id = Id(c.At("id"));
    corner.kind = EnumOf(c.At("kind"),
                         {CornerKind::kTileSeam, CornerKind::kVent, CornerKind::kSmokeDetector,
                          CornerKind::kSprinkler},
                         CornerKindName);
    corner.position = Vec3(c.At("position"));
    world.corner_points.push_back(corner);
  });
  return world;
}

}  // namespace corridorsim::worlds
