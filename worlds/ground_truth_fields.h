#pragma once
// Each world element's fields in ground_truth.json, listed once in the order they are written:
// GroundTruthJson (world_io.cpp) writes an element through its list and ParseGroundTruthJson
// (ground_truth_reader.cpp) reads it back through the same list, so a field cannot be written
// under one key and read under another. What only the writer adds (a plate's texture and number
// region, a door's room) it writes after the list. Internal to worlds/.

#include "worlds/world.h"

namespace corridorsim::worlds::ground_truth_fields {

/// A field only some elements carry, by what the element's earlier fields say: written when
/// `holds(element)`, read (and then required) when it holds of the fields read before it.
template <class Pred>
struct When {
  Pred holds;
};
template <class Pred>
When(Pred) -> When<Pred>;

/// A field only some elements carry: written when `holds(element)`, read when its key is there.
template <class Pred>
struct IfPresent {
  Pred holds;
};
template <class Pred>
IfPresent(Pred) -> IfPresent<Pred>;

/// Fields<T>::Visit(field) calls field(key, member) for every field of T, in the order of
/// ground_truth.json, with a third argument, When or IfPresent, for a field not every T carries.
/// A member is a data member or, for fields only written, a const member function.
template <class T>
struct Fields;

template <>
struct Fields<DoorPlate> {
  template <class Field>
  static void Visit(Field&& field) {
    field("id", &DoorPlate::id);
    field("door_id", &DoorPlate::door_id);
    field("room_number", &DoorPlate::room_number);
    field("center", &DoorPlate::center);
    field("normal", &DoorPlate::normal);
    field("size", &DoorPlate::size_m);
  }
};

template <>
struct Fields<Lamp> {
  template <class Field>
  static void Visit(Field&& field) {
    const auto circular = [](const Lamp& lamp) { return lamp.shape == LampShape::kCircular; };
    const auto panel = [](const Lamp& lamp) { return lamp.shape != LampShape::kCircular; };
    const auto in_room = [](const Lamp& lamp) { return lamp.room_door_id >= 0; };
    field("id", &Lamp::id);
    field("shape", &Lamp::shape);
    field("center", &Lamp::center);
    field("radius", &Lamp::radius_m, When{circular});
    field("size", &Lamp::size_m, When{panel});
    field("on", &Lamp::on);
    field("room_door_id", &Lamp::room_door_id, IfPresent{in_room});
  }
};

template <>
struct Fields<Doorway> {
  template <class Field>
  static void Visit(Field&& field) {
    field("id", &Doorway::id);
    field("state", &Doorway::state);
    field("wall_id", &Doorway::wall_id);
    field("column_a", &Doorway::column_a);
    field("column_b", &Doorway::column_b);
    field("top_height", &Doorway::top_height_m);
    field("width", &Doorway::width_m);
    field("column_width", &Doorway::column_width_m);
    field("inward_normal", &Doorway::inward_normal);
    field("room_number", &Doorway::room_number);
  }
};

template <>
struct Fields<CorridorSegment> {
  template <class Field>
  static void Visit(Field&& field) {
    field("id", &CorridorSegment::id);
    field("start", &CorridorSegment::start);
    field("end", &CorridorSegment::end);
    field("direction", &CorridorSegment::direction);
    field("width", &CorridorSegment::width_m);
    field("height", &CorridorSegment::height_m);
  }
};

template <>
struct Fields<Wall> {
  template <class Field>
  static void Visit(Field&& field) {
    field("id", &Wall::id);
    field("start", &Wall::start);
    field("end", &Wall::end);
    field("inward_normal", &Wall::inward_normal);
    field("segment_id", &Wall::segment_id);
    field("side_wall", &Wall::side_wall);
  }
};

template <>
struct Fields<Reflector> {
  template <class Field>
  static void Visit(Field&& field) {
    field("id", &Reflector::id);
    field("wall_id", &Reflector::wall_id);
    field("mirrored_lamp_id", &Reflector::mirrored_lamp_id);
    field("center", &Reflector::center);
    field("size", &Reflector::size_m);
    field("apparent_lamp_center", &Reflector::apparent_lamp_center);
  }
};

template <>
struct Fields<CornerPoint> {
  template <class Field>
  static void Visit(Field&& field) {
    field("id", &CornerPoint::id);
    field("kind", &CornerPoint::kind);
    field("position", &CornerPoint::position);
  }
};

template <>
struct Fields<Distractor> {
  template <class Field>
  static void Visit(Field&& field) {
    field("id", &Distractor::id);
    field("class", &Distractor::semantic_class);
    field("wall_id", &Distractor::wall_id);
    field("center", &Distractor::center);
    field("size", &Distractor::size_m);
    field("normal", &Distractor::normal);
    field("text", &Distractor::text);
  }
};

}  // namespace corridorsim::worlds::ground_truth_fields
