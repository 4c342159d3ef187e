#include "slam/pipeline.h"

namespace corridorsim::slam {

std::string LandmarkTypeName(LandmarkType type) {
  switch (type) {
    case LandmarkType::kDoorPlate:
      return "door_plate";
    case LandmarkType::kCorner:
      return "corner";
    case LandmarkType::kLamp:
      return "lamp";
    case LandmarkType::kDoor:
      return "door";
    case LandmarkType::kVanishingPoint:
      return "vanishing_point";
  }
  return "unknown";
}

}  // namespace corridorsim::slam
