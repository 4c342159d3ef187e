#include "worlds/world.h"

#include "common/enum_names.h"

namespace corridorsim::worlds {

constexpr EnumName<SemanticClass> kSemanticClassNames[] = {
    {SemanticClass::kUnknown, "unknown"},
    {SemanticClass::kFloor, "floor"},
    {SemanticClass::kWall, "wall"},
    {SemanticClass::kCeiling, "ceiling"},
    {SemanticClass::kDoorFrame, "door_frame"},
    {SemanticClass::kDoorLeaf, "door_leaf"},
    {SemanticClass::kDoorPlate, "door_plate"},
    {SemanticClass::kLampCircular, "lamp_circular"},
    {SemanticClass::kLampPanel, "lamp_panel"},
    {SemanticClass::kReflector, "reflector"},
    {SemanticClass::kVent, "vent"},
    {SemanticClass::kSmokeDetector, "smoke_detector"},
    {SemanticClass::kSprinkler, "sprinkler"},
    {SemanticClass::kPoster, "poster"},
    {SemanticClass::kNoticeBoard, "notice_board"},
    {SemanticClass::kBookshelf, "bookshelf"},
    {SemanticClass::kCabinet, "cabinet"},
    {SemanticClass::kFireExtinguisher, "fire_extinguisher"},
    {SemanticClass::kRoom, "room"}};

std::string SemanticClassName(SemanticClass c) { return NameOf(kSemanticClassNames, c); }

constexpr EnumName<DoorState> kDoorStateNames[] = {
    {DoorState::kClosed, "closed"}, {DoorState::kOpen, "open"}, {DoorState::kEmpty, "empty"}};

std::string DoorStateName(DoorState s) { return NameOf(kDoorStateNames, s); }

std::string LampShapeName(LampShape s) { return s == LampShape::kCircular ? "circular" : "panel"; }

constexpr EnumName<CornerKind> kCornerKindNames[] = {{CornerKind::kTileSeam, "tile_seam"},
                                                     {CornerKind::kVent, "vent"},
                                                     {CornerKind::kSmokeDetector, "smoke_detector"},
                                                     {CornerKind::kSprinkler, "sprinkler"}};

std::string CornerKindName(CornerKind k) { return NameOf(kCornerKindNames, k); }

std::size_t World::triangle_count() const {
  std::size_t n = 0;
  for (const Mesh& m : meshes) n += m.triangle_count();
  return n;
}

}  // namespace corridorsim::worlds
