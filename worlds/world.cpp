#include "worlds/world.h"

#include <algorithm>
#include <cmath>

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

Eigen::Vector3f BlackBodyColour(double kelvin) {
  const double t = std::clamp(kelvin, 1000.0, 40000.0) / 100.0;
  double r = 255, g = 0, b = 255;
  if (t <= 66) {
    g = 99.4708025861 * std::log(t) - 161.1195681661;
    b = t <= 19 ? 0.0 : 138.5177312231 * std::log(t - 10) - 305.0447927307;
  } else {
    r = 329.698727446 * std::pow(t - 60, -0.1332047592);
    g = 288.1221695283 * std::pow(t - 60, -0.0755148492);
  }
  Eigen::Vector3d c(r, g, b);
  for (int k = 0; k < 3; ++k) c[k] = std::pow(std::clamp(c[k], 0.0, 255.0) / 255.0, 2.2);
  return (c / c.maxCoeff()).cast<float>();
}

}  // namespace corridorsim::worlds
