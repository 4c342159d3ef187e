#include "worlds/ground_truth_reader.h"

#include <climits>
#include <initializer_list>

#include "common/io/json_input.h"
#include "worlds/ground_truth_fields.h"

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

// A field's value from ground_truth.json: ids in int's range, vectors of 2 or 3 numbers, enums by
// name.
void Read(const JsonField& f, int& v) { v = Id(f); }
void Read(const JsonField& f, bool& v) { v = f.Bool(); }
void Read(const JsonField& f, double& v) { v = f.Number(); }
void Read(const JsonField& f, std::string& v) { v = f.String(); }
void Read(const JsonField& f, Eigen::Vector2d& v) { v = Vec2(f); }
void Read(const JsonField& f, Eigen::Vector3d& v) { v = Vec3(f); }
void Read(const JsonField& f, LampShape& v) {
  v = EnumOf(f, {LampShape::kCircular, LampShape::kPanel}, LampShapeName);
}
void Read(const JsonField& f, DoorState& v) {
  v = EnumOf(f, {DoorState::kClosed, DoorState::kOpen, DoorState::kEmpty}, DoorStateName);
}
void Read(const JsonField& f, CornerKind& v) {
  v = EnumOf(f,
             {CornerKind::kTileSeam, CornerKind::kVent, CornerKind::kSmokeDetector,
              CornerKind::kSprinkler},
             CornerKindName);
}

// Whether an element carries a field: a When field when its earlier fields say so, an IfPresent
// field when its key is there.
template <class Pred, class T>
bool Carries(const ground_truth_fields::When<Pred>& only, const T& read_so_far, const JsonField&,
             const char*) {
  return only.holds(read_so_far);
}
template <class Pred, class T>
bool Carries(const ground_truth_fields::IfPresent<Pred>&, const T&, const JsonField& element,
             const char* key) {
  return element.Has(key);
}

// An element of type T read through its field list (ground_truth_fields.h), field by field in
// the order of the list.
template <class T>
T ElementOf(const JsonField& element) {
  T item;
  ground_truth_fields::Fields<T>::Visit([&](const char* key, auto member, const auto&... only) {
    if ((Carries(only, item, element, key) && ...)) Read(element.At(key), item.*member);
  });
  return item;
}

}  // namespace

World ParseGroundTruthJson(std::string_view text, const std::string& file) {
  const Json document = ParseJsonInput(text, file);
  const JsonField top{file, "", document};
  World world;
  world.seed = top.At("seed").Unsigned();
  ForEach(top, "door_plates",
          [&](const JsonField& p) { world.plates.push_back(ElementOf<DoorPlate>(p)); });
  ForEach(top, "lamps", [&](const JsonField& l) { world.lamps.push_back(ElementOf<Lamp>(l)); });
  ForEach(top, "doors", [&](const JsonField& d) { world.doors.push_back(ElementOf<Doorway>(d)); });
  ForEach(top, "reflectors",
          [&](const JsonField& r) { world.reflectors.push_back(ElementOf<Reflector>(r)); });
  ForEach(top, "corner_points",
          [&](const JsonField& c) { world.corner_points.push_back(ElementOf<CornerPoint>(c)); });
  return world;
}

}  // namespace corridorsim::worlds
