#include "slam/pipeline.h"

#include "common/enum_names.h"

namespace corridorsim::slam {

constexpr EnumName<LandmarkType> kLandmarkTypeNames[] = {
    {LandmarkType::kDoorPlate, "door_plate"},
    {LandmarkType::kCorner, "corner"},
    {LandmarkType::kLamp, "lamp"},
    {LandmarkType::kDoor, "door"},
    {LandmarkType::kVanishingPoint, "vanishing_point"}};

std::string LandmarkTypeName(LandmarkType type) { return NameOf(kLandmarkTypeNames, type); }

}  // namespace corridorsim::slam
