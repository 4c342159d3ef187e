#include "harness/run/run_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/io/outside_text.h"
#include "common/io/stable_json.h"
#include "worlds/world.h"

namespace corridorsim {

std::string StampSeconds(TimeNs stamp_ns) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%lld.%09lld",
                static_cast<long long>(stamp_ns / kNanosecondsPerSecond),
                static_cast<long long>(stamp_ns % kNanosecondsPerSecond));
  return buf;
}

std::string CsvNumber(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.9g", value);
  return buf;
}

namespace {

constexpr double kSlipStepsPerM = 1e9;  // slips are often far below a micrometre

}  // namespace

nlohmann::ordered_json EventJson(const sim::Event& e) {
  nlohmann::ordered_json j;
  j["t"] = RoundToStep(ToSeconds(e.stamp_ns), json_steps::kSeconds);  // t_ns is exact
  j["t_ns"] = e.stamp_ns;
  j["type"] = sim::EventKindName(e.kind);
  switch (e.kind) {
    case sim::EventKind::kCollisionBegin:
    case sim::EventKind::kCollisionEnd: {
      j["object_id"] = e.instance_id;
      j["object_class"] = worlds::SemanticClassName(e.semantic_class);
      j["position"] = RoundedJson(e.position_in_world, json_steps::kMetres);
      if (e.kind == sim::EventKind::kCollisionBegin) {
        j["depth_m"] = RoundToStep(e.depth_m, json_steps::kMetres);
      }
      break;
    }
    case sim::EventKind::kSlip:
      j["wheel"] = e.left_wheel ? "left" : "right";
      j["extra_distance_m"] = RoundToStep(e.distance_m, kSlipStepsPerM);
      break;
    case sim::EventKind::kFrameDropped:
      j["camera"] = e.camera_id;
      break;
    case sim::EventKind::kPathDone:
    case sim::EventKind::kTimeout:
      break;
  }
  return j;
}

std::string OvEvalHeader() {
  return "# timestamp(s) tx ty tz qx qy qz qw Pr11 Pr12 Pr13 Pr22 Pr23 Pr33 Pt11 Pt12 Pt13 Pt22 "
         "Pt23 Pt33\n";
}

std::string OvEvalLine(TimeNs stamp_ns, const SE2& pose, const Eigen::Matrix3d& p) {
  const std::string tum = sim::TumLine(stamp_ns, SE3::FromSE2(pose));
  char buf[320];
  std::snprintf(buf, sizeof(buf), " 0 0 0 0 0 %.9e %.9e %.9e 0 %.9e 0 0", p(2, 2), p(0, 0), p(0, 1),
                p(1, 1));
  return tum + buf;
}

}  // namespace corridorsim

namespace corridorsim {
namespace {

nlohmann::ordered_json CovarianceJson(const Eigen::Matrix3d& c) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (int i = 0; i < 3; ++i) {
    rows.push_back(RoundedJson(Eigen::Vector3d(c.row(i).transpose()), 1e12));
  }
  return rows;
}

// A number for the detections CSV: empty when NaN (no value), else shortest round-trip text.
std::string CsvNumber(double v, int decimals) {
  if (std::isnan(v)) return "";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

}  // namespace

nlohmann::ordered_json LandmarksJson(const std::vector<slam::LandmarkEstimate>& landmarks) {
  std::vector<const slam::LandmarkEstimate*> sorted;
  for (const slam::LandmarkEstimate& l : landmarks) sorted.push_back(&l);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto* a, const auto* b) { return a->id < b->id; });
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const slam::LandmarkEstimate* l : sorted) {
    nlohmann::ordered_json j;
    j["id"] = l->id;
    j["type"] = slam::LandmarkTypeName(l->type);
    j["status"] = slam::LandmarkStatusName(l->status);
    j["label"] = l->label;
    j["position_in_world"] = RoundedJson(l->position_in_world, json_steps::kMetres);
    j["covariance"] = CovarianceJson(l->covariance);
    if (!l->points.empty()) {
      nlohmann::ordered_json points = nlohmann::ordered_json::array();
      for (const slam::LandmarkPoint& p : l->points) {
        points.push_back(
            {{"role", p.role},
             {"position_in_world", RoundedJson(p.position_in_world, json_steps::kMetres)},
             {"covariance", CovarianceJson(p.covariance)}});
      }
      j["points"] = std::move(points);
    }
    out.push_back(std::move(j));
  }
  return out;
}

std::string DetectionsCsv(const std::vector<slam::Detection>& detections) {
  std::string csv =
      "stamp_s,camera,type,u_px,v_px,box_min_x_px,box_min_y_px,box_max_x_px,box_max_y_px,"
      "plate_box,radius_px,label,open,score,recognition_score,landmark_id,new_landmark,"
      "bearing_a_rad,bearing_b_rad\n";
  for (const slam::Detection& d : detections) {
    // A declared measurement type's detection has a box when it gave one (min < max).
    const bool boxed =
        d.Is(slam::LandmarkType::kDoorPlate) || d.Is(slam::LandmarkType::kDoor) ||
        (!d.measurement.empty() && d.box_px[0] < d.box_px[2] && d.box_px[1] < d.box_px[3]);
    csv += CsvNumber(ToSeconds(d.stamp_ns), 9) + "," + d.camera_id + "," +
           slam::MeasurementName(d) + "," + CsvNumber(d.pixel.x(), 4) + "," +
           CsvNumber(d.pixel.y(), 4) + ",";
    for (int i = 0; i < 4; ++i) csv += (boxed ? CsvNumber(d.box_px[i], 4) : "") + ",";
    csv += std::string(
               d.Is(slam::LandmarkType::kDoorPlate)
                   ? (d.plate_box == slam::PlateBox::kNumberRegion ? "number_region" : "outline")
                   : "") +
           ",";
    csv += (d.Is(slam::LandmarkType::kLamp) ? CsvNumber(d.radius_px, 4) : "") + ",";
    // Labels are room numbers (digits); anything else is quoted as CSV requires, and a plugin's
    // bytes that are not UTF-8 become U+FFFD (the file stays text for every reader).
    std::string label = ValidUtf8(d.label);
    if (label.find_first_of(",\"\n\r") != std::string::npos) {
      std::string quoted = "\"";
      for (const char c : label) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
      label = quoted + "\"";
    }
    csv += label + ",";
    csv += std::string(d.open ? (*d.open ? "1" : "0") : "") + ",";
    csv += CsvNumber(d.score, 6) + "," + CsvNumber(d.recognition_score, 6) + "," +
           std::to_string(d.landmark_id) + "," + (d.new_landmark ? "1" : "0") + ",";
    // Doors: the columns' bearings (P3 eq. 17), empty when none.
    csv += CsvNumber(d.column_bearings_rad(0), 8) + "," + CsvNumber(d.column_bearings_rad(1), 8) +
           "\n";
  }
  return csv;
}

}  // namespace corridorsim
