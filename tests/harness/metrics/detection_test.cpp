// Tests harness/metrics/detection.cpp: detector precision, recall and errors against the frame
// truth. Each case is constructed so that its answer is known in closed form.
#include "harness/metrics/detection.h"

#include <functional>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/harness/metrics/support.h"
#include "tests/support/tolerances.h"

namespace corridorsim::metrics_tests {
namespace {

TEST_CASE("detector precision, recall, IoU, centre error and door state against frame truth",
          "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = Record("detectors", truth, [](const SE2& p) { return p; });
  record.cameras_used = {"front", "lateral", "upward"};

  FrameTruthSample lateral = Frame("lateral", 5);
  const auto plate = [](int id, double x0, double x1, bool full) {
    render::PlateTruth p;
    p.id = id;
    p.room_number = std::to_string(100 + id);
    p.bbox_min_px = Vector2d(x0, 100);
    p.bbox_max_px = Vector2d(x1, 150);
    p.center_px = Vector2d((x0 + x1) / 2, 125);
    p.fully_in_image = full;
    p.visible_fraction = 1.0;
    return p;
  };
  lateral.truth.plates = {plate(1, 100, 200, true), plate(2, 300, 400, true),
                          plate(3, 600, 640, false)};  // cut by the border: not scored
  const auto plate_detection = [](const Vector4d& box, const std::string& label) {
    slam::Detection d;
    d.stamp_ns = 5;
    d.camera_id = "lateral";
    d.type = LandmarkType::kDoorPlate;
    d.box_px = box;
    d.pixel = 0.5 * (box.head<2>() + box.tail<2>());
    d.label = label;
    return d;
  };
  record.detections.push_back(plate_detection({105, 100, 205, 150}, "101"));  // IoU 4750/5250
  record.detections.push_back(plate_detection({500, 300, 520, 310}, ""));     // nothing there
  record.detections.push_back(plate_detection({600, 100, 640, 150}, "103"));  // the cut plate

  FrameTruthSample upward = Frame("upward", 5);
  const auto lamp = [](int id, const Vector2d& c, double r) {
    render::LampTruth l;
    l.id = id;
    l.center_px = c;
    l.radius_px = r;
    l.visible_fraction = 1.0;
    return l;
  };
  upward.truth.lamps = {lamp(1, {320, 240}, 20), lamp(2, {100, 100}, 15)};
  render::DoorTruth door;
  door.id = 3;
  door.state = worlds::DoorState::kOpen;
  door.column_a_px = Vector2d(200, 300);
  door.column_b_px = Vector2d(260, 300);
  door.visible = true;
  upward.truth.doors = {door};
  const auto upward_detection = [](LandmarkType type, const Vector2d& px) {
    slam::Detection d;
    d.stamp_ns = 5;
    d.camera_id = "upward";
    d.type = type;
    d.pixel = px;
    return d;
  };
  record.detections.push_back(upward_detection(LandmarkType::kLamp, {323, 244}));  // 5 px off
  record.detections.push_back(upward_detection(LandmarkType::kLamp, {500, 400}));  // nothing
  slam::Detection door_detection = upward_detection(LandmarkType::kDoor, {230, 300});
  door_detection.box_px = Vector4d(198, 290, 262, 310);
  door_detection.open = true;
  record.detections.push_back(door_detection);

  FrameTruthSample front = Frame("front", 5);
  render::VanishingPointTruth vp;
  vp.direction_in_world = Vector2d(1, 0);
  vp.pixel = Vector2d(320, 240);
  vp.in_image = true;
  vp.camera_in_segment = true;
  front.truth.vanishing_points = {vp};
  slam::Detection vp_detection;
  vp_detection.stamp_ns = 5;
  vp_detection.camera_id = "front";
  vp_detection.type = LandmarkType::kVanishingPoint;
  vp_detection.pixel = Vector2d(323, 244);
  record.detections.push_back(vp_detection);

  const Json m = RunOne(world, truth, record, {front, lateral, upward});
  REQUIRE(m.contains("detection"));
  const Json& plates = m["detection"]["door_plate"];
  CHECK(plates["detections"] == 3);
  CHECK(plates["true_positives"] == 1);
  CHECK(plates["false_positives"] == 1);
  CHECK(plates["false_negatives"] == 1);
  CHECK(plates["ignored"] == 1);
  CHECK(Num(plates["precision"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  CHECK(Num(plates["recall"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  CHECK(Num(plates["mean_iou"]) == Approx(4750.0 / 5250.0).margin(test::kMetricsJsonRatio));
  CHECK(Num(plates["room_number_accuracy"]) == 1.0);
  const Json& lamps = m["detection"]["lamp"];
  CHECK(Num(lamps["precision"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  CHECK(Num(lamps["recall"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  CHECK(Num(lamps["mean_center_error_px"]) == Approx(5.0).margin(test::kMetricsJsonPx));
  const Json& doors = m["detection"]["door"];
  CHECK(Num(doors["precision"]) == 1.0);
  CHECK(Num(doors["recall"]) == 1.0);
  CHECK(Num(doors["open_state_accuracy"]) == 1.0);
  const Json& vps = m["detection"]["vanishing_point"];
  CHECK(vps["count"] == 1);
  CHECK(Num(vps["mean_error_px"]) == Approx(5.0).margin(test::kMetricsJsonPx));
  CHECK(Num(vps["mean_abs_u_error_px"]) == Approx(3.0).margin(test::kMetricsJsonPx));
  CHECK(Num(vps["detected_frame_fraction"]) == 1.0);
  CHECK(m["timing"]["frames"] == 3);

  SECTION("every scalar in the pipeline's object is a known metric name") {
    const std::vector<std::string> names_list = MetricNames();
    const std::set<std::string> names(names_list.begin(), names_list.end());
    std::vector<std::string> unknown;
    std::function<void(const Json&, const std::string&)> walk = [&](const Json& j,
                                                                    const std::string& path) {
      if (j.is_object()) {
        for (const auto& [key, value] : j.items()) {
          walk(value, path.empty() ? key : path + "." + key);
        }
      } else if (path.rfind("timing.stage_", 0) != 0 && names.count(path) == 0) {
        unknown.push_back(path);
      }
    };
    walk(m, "");
    CHECK(unknown.empty());
  }
}

}  // namespace
}  // namespace corridorsim::metrics_tests
