#include "slam/pipeline.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "common/enum_names.h"
#include "common/options_checker.h"
#include "common/wheel_odometry_model.h"

namespace corridorsim::slam {

std::optional<OptionsProblem> Calibration::Check() const {
  OptionsChecker c;
  c.Positive(wheelbase_m, "wheelbase_m");
  c.Positive(wheel_diameter_m, "wheel_diameter_m");
  c.Require(ticks_per_revolution >= 0 && ticks_per_revolution <= kMaxTicksPerRevolution,
            "ticks_per_revolution",
            "must lie in [0, " + std::to_string(kMaxTicksPerRevolution) + "] (got " +
                std::to_string(ticks_per_revolution) + ")");
  for (const CameraCalibration& camera : cameras) {
    const std::string key = "cameras." + camera.id + ".";
    if (const std::optional<std::string> problem = camera.model.Check()) {
      c.Require(false, key + "model", *problem);
    }
    if (camera.depth) {
      c.NonNegative(camera.depth->min_m, key + "depth.min_m");
      c.Require(camera.depth->max_m > camera.depth->min_m, key + "depth.max_m",
                "must be greater than depth.min_m (got " + FormatNumber(camera.depth->max_m) +
                    " <= " + FormatNumber(camera.depth->min_m) + ")");
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

namespace corridorsim::slam {

constexpr EnumName<LandmarkStatus> kLandmarkStatusNames[] = {
    {LandmarkStatus::kInitializing, "initializing"}, {LandmarkStatus::kConverged, "converged"}};

std::string LandmarkStatusName(LandmarkStatus status) {
  return NameOf(kLandmarkStatusNames, status);
}

bool IsMeasurementTypeName(const std::string& name) {
  const bool syntax = !name.empty() && name.size() <= kMaxMeasurementNameLength && name[0] >= 'a' &&
                      name[0] <= 'z' && std::all_of(name.begin(), name.end(), [](char c) {
                        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
                      });
  return syntax && std::none_of(std::begin(kLandmarkTypeNames), std::end(kLandmarkTypeNames),
                                [&name](const auto& entry) { return name == entry.name; });
}

std::optional<std::string> MeasurementTypesProblem(const std::vector<MeasurementType>& types) {
  if (types.size() > static_cast<std::size_t>(kMaxMeasurementTypes)) {
    return "declares " + std::to_string(types.size()) + " measurement types (at most " +
           std::to_string(kMaxMeasurementTypes) + ")";
  }
  for (std::size_t i = 0; i < types.size(); ++i) {
    const MeasurementType& t = types[i];
    if (!IsMeasurementTypeName(t.name)) {
      return "declares measurement type number " + std::to_string(i + 1) +
             " with a name that is not [a-z][a-z0-9_]{0," +
             std::to_string(kMaxMeasurementNameLength - 1) +
             "} or is a shipped landmark type's (those need no declaration)";
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (types[j].name == t.name) return "declares the measurement type '" + t.name + "' twice";
    }
    if (t.dof < 1 || t.dof > kMaxMeasurementDof) {
      return "declares the measurement type '" + t.name + "' with " + std::to_string(t.dof) +
             " degrees of freedom (1 to " + std::to_string(kMaxMeasurementDof) + ")";
    }
  }
  return std::nullopt;
}

std::string MeasurementName(const Detection& detection) {
  return detection.measurement.empty() ? LandmarkTypeName(detection.type) : detection.measurement;
}

std::string MeasurementName(const Innovation& innovation) {
  return innovation.measurement.empty() ? LandmarkTypeName(innovation.type)
                                        : innovation.measurement;
}

std::optional<std::string> DetectionProblem(const Detection& d) {
  if (d.camera_id.empty()) return "has no camera id";
  if (!d.pixel.allFinite()) return "has a non-finite pixel";
  if (!d.box_px.allFinite()) return "has a non-finite box";
  if (!std::isnan(d.score) && !std::isfinite(d.score)) return "has an infinite score";
  if (!d.measurement.empty()) {
    // A type of the pipeline's own: none of the shipped types' fields.
    if (!d.label.empty() || d.open || d.radius_px != 0.0 || !std::isnan(d.recognition_score) ||
        !d.column_bearings_rad.array().isNaN().all()) {
      return "is of the measurement type '" + d.measurement +
             "' with a field of a shipped type (label, open, radius, recognition score or "
             "column bearings)";
    }
    return std::nullopt;
  }
  if (!std::isnan(d.recognition_score) &&
      !(d.recognition_score >= 0.0 && d.recognition_score <= 1.0)) {
    return "has a recognition score outside [0, 1]";
  }
  const bool has_box = d.box_px[0] < d.box_px[2] && d.box_px[1] < d.box_px[3];
  switch (d.type) {
    case LandmarkType::kDoorPlate:
      if (!has_box) return "is a door plate without a box (min x < max x, min y < max y)";
      break;
    case LandmarkType::kDoor:
      if (!has_box) return "is a door without a box (min x < max x, min y < max y)";
      if (!d.label.empty()) return "is a door with a label";
      break;
    case LandmarkType::kLamp:
      if (!(d.radius_px > 0.0)) return "is a lamp without a positive radius";
      if (!d.label.empty()) return "is a lamp with a label";
      break;
    case LandmarkType::kCorner:
    case LandmarkType::kVanishingPoint:
      if (!d.label.empty()) return "is a " + LandmarkTypeName(d.type) + " with a label";
      break;
  }
  if (d.type != LandmarkType::kDoorPlate && !std::isnan(d.recognition_score)) {
    return "has a recognition score but is not a door plate";
  }
  if (d.type != LandmarkType::kDoor && d.open) return "has an open state but is not a door";
  const Eigen::Vector2d& b = d.column_bearings_rad;
  if (d.type != LandmarkType::kDoor && !b.array().isNaN().all()) {
    return "has column bearings but is not a door";
  }
  if (!b.array().isNaN().all() &&
      !(b.allFinite() && b.cwiseAbs().maxCoeff() <= std::numbers::pi + 1e-9)) {
    return "has column bearings that are not both angles in [-pi, pi]";
  }
  return std::nullopt;
}

}  // namespace corridorsim::slam
