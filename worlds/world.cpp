#include "worlds/world.h"

namespace corridorsim::worlds {

std::string SemanticClassName(SemanticClass c) {
  switch (c) {
    case SemanticClass::kUnknown:
      return "unknown";
    case SemanticClass::kFloor:
      return "floor";
    case SemanticClass::kWall:
      return "wall";
    case SemanticClass::kCeiling:
      return "ceiling";
    case SemanticClass::kDoorFrame:
      return "door_frame";
    case SemanticClass::kDoorLeaf:
      return "door_leaf";
    case SemanticClass::kDoorPlate:
      return "door_plate";
    case SemanticClass::kLampCircular:
      return "lamp_circular";
    case SemanticClass::kLampPanel:
      return "lamp_panel";
    case SemanticClass::kReflector:
      return "reflector";
    case SemanticClass::kVent:
      return "vent";
    case SemanticClass::kSmokeDetector:
      return "smoke_detector";
    case SemanticClass::kSprinkler:
      return "sprinkler";
    case SemanticClass::kPoster:
      return "poster";
    case SemanticClass::kNoticeBoard:
      return "notice_board";
    case SemanticClass::kBookshelf:
      return "bookshelf";
    case SemanticClass::kCabinet:
      return "cabinet";
    case SemanticClass::kFireExtinguisher:
      return "fire_extinguisher";
    case SemanticClass::kRoom:
      return "room";
  }
  return "unknown";
}

std::string DoorStateName(DoorState s) {
  switch (s) {
    case DoorState::kClosed:
      return "closed";
    case DoorState::kOpen:
      return "open";
    case DoorState::kEmpty:
      return "empty";
  }
  return "?";
}

std::string LampShapeName(LampShape s) { return s == LampShape::kCircular ? "circular" : "panel"; }

std::string CornerKindName(CornerKind k) {
  switch (k) {
    case CornerKind::kTileSeam:
      return "tile_seam";
    case CornerKind::kVent:
      return "vent";
    case CornerKind::kSmokeDetector:
      return "smoke_detector";
    case CornerKind::kSprinkler:
      return "sprinkler";
  }
  return "?";
}

std::size_t World::triangle_count() const {
  std::size_t n = 0;
  for (const Mesh& m : meshes) n += m.triangle_count();
  return n;
}

}  // namespace corridorsim::worlds
