#include "slam/pipeline.h"

#include "common/enum_names.h"
#include "common/options_checker.h"

namespace corridorsim::slam {

std::optional<OptionsProblem> Calibration::Check() const {
  OptionsChecker c;
  c.Positive(wheelbase_m, "wheelbase_m");
  c.Positive(wheel_diameter_m, "wheel_diameter_m");
  c.Require(ticks_per_revolution >= 0, "ticks_per_revolution", "must not be negative");
  for (const CameraCalibration& camera : cameras) {
    const std::string key = "cameras." + camera.id + ".";
    if (const std::optional<std::string> problem = camera.model.Check()) {
      c.Require(false, key + "model", *problem);
    }
    if (camera.depth) {
      c.NonNegative(camera.depth->min_m, key + "depth.min_m");
      c.Require(camera.depth->max_m > camera.depth->min_m, key + "depth.max_m",
                "must be greater than depth.min_m");
    }
  }
  return c.problem();
}

constexpr EnumName<LandmarkType> kLandmarkTypeNames[] = {
    {LandmarkType::kDoorPlate, "door_plate"},
    {LandmarkType::kCorner, "corner"},
    {LandmarkType::kLamp, "lamp"},
    {LandmarkType::kDoor, "door"},
    {LandmarkType::kVanishingPoint, "vanishing_point"}};

std::string LandmarkTypeName(LandmarkType type) { return NameOf(kLandmarkTypeNames, type); }

}  // namespace corridorsim::slam
