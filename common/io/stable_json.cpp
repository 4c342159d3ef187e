#include "common/io/stable_json.h"

#include <cmath>

namespace corridorsim {

double RoundToStep(double value, double steps_per_unit) {
  return std::round(value * steps_per_unit) / steps_per_unit + 0.0;  // + 0.0: -0 becomes 0
}

nlohmann::ordered_json RoundedJson(const Eigen::Vector2d& v, double steps_per_unit) {
  return nlohmann::ordered_json::array(
      {RoundToStep(v.x(), steps_per_unit), RoundToStep(v.y(), steps_per_unit)});
}

nlohmann::ordered_json RoundedJson(const Eigen::Vector3d& v, double steps_per_unit) {
  return nlohmann::ordered_json::array({RoundToStep(v.x(), steps_per_unit),
                                        RoundToStep(v.y(), steps_per_unit),
                                        RoundToStep(v.z(), steps_per_unit)});
}

nlohmann::ordered_json PoseJson(const SE3& pose) {
  const Eigen::Vector4d coeffs = pose.quaternion().coeffs();  // x, y, z, w
  const Eigen::Vector4d q = coeffs.w() < 0.0 ? Eigen::Vector4d(-coeffs) : coeffs;
  nlohmann::ordered_json json;
  json["t"] = RoundedJson(Eigen::Vector3d(pose.translation()), json_steps::kMetres);
  json["q"] = nlohmann::ordered_json::array(
      {RoundToStep(q.x(), json_steps::kUnitVector), RoundToStep(q.y(), json_steps::kUnitVector),
       RoundToStep(q.z(), json_steps::kUnitVector), RoundToStep(q.w(), json_steps::kUnitVector)});
  return json;
}

void RoundNumbers(nlohmann::ordered_json& json, double steps_per_unit) {
  if (json.is_number_float()) {
    json = RoundToStep(json.get<double>(), steps_per_unit);
  } else if (json.is_structured()) {
    for (nlohmann::ordered_json& element : json) RoundNumbers(element, steps_per_unit);
  }
}

}  // namespace corridorsim
