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

slam::Detection VpDetection(TimeNs stamp, const Vector2d& pixel) {
  return DetectionAt(stamp, "front", LandmarkType::kVanishingPoint, pixel);
}

FrameTruthSample VpFrame(TimeNs stamp, const Vector2d& pixel) {
  FrameTruthSample f = Frame("front", stamp);
  render::VanishingPointTruth vp;
  vp.direction_in_world = Vector2d(1, 0);
  vp.pixel = pixel;
  vp.in_image = true;
  vp.camera_in_segment = true;
  f.truth.vanishing_points = {vp};
  return f;
}

slam::Detection PlateDetection(TimeNs stamp, const Vector4d& box, slam::PlateBox kind) {
  slam::Detection d = DetectionAt(stamp, "lateral", LandmarkType::kDoorPlate,
                                  0.5 * (box.head<2>() + box.tail<2>()));
  d.box_px = box;
  d.plate_box = kind;
  return d;
}

TEST_CASE(
    "lamps: only lit circular lamps are to be found; panels and dark lamps rejected; "
    "border-cut lamps apart",
    "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("lamps", truth, {"upward"});
  FrameTruthSample upward = Frame("upward", 5);
  const auto lamp = [](int id, const Vector2d& c, worlds::LampShape shape, bool on, bool cut,
                       double visible) {
    render::LampTruth l;
    l.id = id;
    l.center_px = c;
    l.radius_px = 15;
    l.shape = shape;
    l.on = on;
    l.cut_by_border = cut;
    l.visible_fraction = visible;
    return l;
  };
  using worlds::LampShape;
  upward.truth.lamps = {
      lamp(1, {100, 100}, LampShape::kCircular, true, false, 1.0),   // found, 1 px off
      lamp(2, {300, 100}, LampShape::kCircular, true, false, 1.0),   // missed
      lamp(3, {500, 100}, LampShape::kPanel, true, false, 1.0),      // taken for a lamp
      lamp(4, {100, 300}, LampShape::kPanel, true, false, 1.0),      // rejected
      lamp(5, {300, 300}, LampShape::kCircular, false, false, 1.0),  // dark, rejected
      lamp(6, {630, 300}, LampShape::kCircular, true, true, 0.6),    // cut, found 2 px off
      lamp(7, {630, 450}, LampShape::kCircular, true, true, 0.7),    // cut, missed
      lamp(8, {300, 450}, LampShape::kCircular, true, false, 0.2),   // mostly hidden
  };
  const auto at = [](const Vector2d& px) {
    slam::Detection d = DetectionAt(5, "upward", LandmarkType::kLamp, px);
    d.radius_px = 15;
    return d;
  };
  for (const Vector2d& px : {Vector2d(101, 100), Vector2d(500, 102), Vector2d(632, 300),
                             Vector2d(300, 451), Vector2d(50, 450)}) {
    record.detections.push_back(at(px));
  }
  const Json m = RunOne(world, truth, record, {upward});
  const Json& lamps = m["detection"]["lamp"];
  CHECK(lamps["detections"] == 5);
  CHECK(lamps["true_positives"] == 1);
  CHECK(lamps["false_negatives"] == 1);
  CHECK(lamps["false_positives"] == 2);  // the panel taken for a lamp, the one at (50, 450)
  CHECK(lamps["ignored"] == 1);          // the mostly hidden lamp's detection
  CHECK(Num(lamps["recall"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  CHECK(Num(lamps["max_center_error_px"]) == Approx(1.0).margin(test::kMetricsJsonPx));
  CHECK(lamps["to_reject"] == 3);
  CHECK(lamps["rejected"] == 2);
  CHECK(lamps["border_cut"] == 2);
  CHECK(lamps["border_cut_found"] == 1);
  CHECK(Num(lamps["border_cut_max_center_error_px"]) == Approx(2.0).margin(test::kMetricsJsonPx));
}

TEST_CASE("detector precision, recall, IoU, centre error and door state against frame truth",
          "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("detectors", truth, {"front", "lateral", "upward"});

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
    slam::Detection d = PlateDetection(5, box, slam::PlateBox::kOutline);  // the whole plate
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
  // A lamp 5 px off lamp 1, and one where there is nothing.
  record.detections.push_back(DetectionAt(5, "upward", LandmarkType::kLamp, {323, 244}));
  record.detections.push_back(DetectionAt(5, "upward", LandmarkType::kLamp, {500, 400}));
  slam::Detection door_detection = DetectionAt(5, "upward", LandmarkType::kDoor, {230, 300});
  door_detection.box_px = Vector4d(198, 290, 262, 310);
  door_detection.open = true;
  record.detections.push_back(door_detection);

  const FrameTruthSample front = VpFrame(5, {320, 240});
  record.detections.push_back(VpDetection(5, {323, 244}));

  const Json m = RunOne(world, truth, record, {front, lateral, upward});
  REQUIRE(m.contains("detection"));
  const Json& plates = m["detection"]["door_plate"];
  CheckCounts(plates, {{"detections", 3},
                       {"true_positives", 1},
                       {"false_positives", 1},
                       {"false_negatives", 1},
                       {"ignored", 1}});
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

TEST_CASE("a vanishing-point detection far from the true vanishing point is not a hit",
          "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("vp", truth, {"front"});
  // Frame 5: 5 px off (a hit); frame 6: 100 px off (a false positive, and the frame is not
  // detected); frame 7: nothing detected.
  record.detections = {VpDetection(5, {323, 244}), VpDetection(6, {420, 240})};
  const Json m = RunOne(world, truth, record,
                        {VpFrame(5, {320, 240}), VpFrame(6, {320, 240}), VpFrame(7, {320, 240})});
  const Json& vps = m["detection"]["vanishing_point"];
  CHECK(vps["count"] == 2);
  CHECK(vps["hits"] == 1);
  CHECK(vps["false_positives"] == 1);
  CHECK(Num(vps["precision"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  CHECK(Num(vps["detected_frame_fraction"]) == Approx(1.0 / 3.0).margin(test::kMetricsJsonRatio));
}

render::PlateTruth PlateWithRegions(int id, double distance_m, double height_px,
                                    double viewing_angle_deg) {
  render::PlateTruth p;
  p.id = id;
  p.room_number = std::to_string(200 + id);
  p.bbox_min_px = Vector2d(100, 100);
  p.bbox_max_px = Vector2d(100 + 2 * height_px, 100 + height_px);
  p.center_px = 0.5 * (p.bbox_min_px + p.bbox_max_px);
  p.distance_m = distance_m;
  p.viewing_angle_deg = viewing_angle_deg;
  p.fully_in_image = true;
  p.visible_fraction = 1.0;
  return p;
}

// The plate cases: a pipeline whose estimates are the truth and that used the lateral camera.
struct LateralPlates {
  const worlds::World world{};
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("plates", truth, {"lateral"});
};

TEST_CASE_METHOD(LateralPlates,
                 "a plate is scored only where it was legible: large enough and not too oblique",
                 "[metrics]") {
  FrameTruthSample legible = Frame("lateral", 5);
  legible.truth.plates = {PlateWithRegions(1, 1.2, 40, 10)};
  FrameTruthSample tiny = Frame("lateral", 6);  // a dot far ahead: 4 px high
  tiny.truth.plates = {PlateWithRegions(2, 20.0, 4, 10)};
  FrameTruthSample oblique = Frame("lateral", 7);  // seen at 80 deg to its normal
  oblique.truth.plates = {PlateWithRegions(3, 1.5, 40, 80)};
  // No detection anywhere: only the legible plate is a miss.
  record.detections = {PlateDetection(5, {500, 400, 520, 410}, slam::PlateBox::kOutline)};
  const Json m = RunOne(world, truth, record, {legible, tiny, oblique});
  const Json& plates = m["detection"]["door_plate"];
  CHECK(plates["false_negatives"] == 1);
  CHECK(plates["false_positives"] == 1);
  CHECK(plates["true_positives"] == 0);
}

TEST_CASE_METHOD(LateralPlates,
                 "a plate detection is matched to the number region or the outline, as it reports",
                 "[metrics]") {
  // A plate 100 x 50 px whose number region is the middle 60 x 20 px.
  FrameTruthSample frame = Frame("lateral", 5);
  render::PlateTruth plate = PlateWithRegions(1, 1.2, 50, 0);
  plate.number_bbox_min_px = Vector2d(120, 115);
  plate.number_bbox_max_px = Vector2d(180, 135);
  frame.truth.plates = {plate};
  FrameTruthSample frame2 = Frame("lateral", 6);
  frame2.truth.plates = {plate};
  // P1-style: the number region (IoU 1 with the region, 0.24 with the outline) is a hit; the
  // outline reported as an outline is a hit too.
  record.detections = {PlateDetection(5, {120, 115, 180, 135}, slam::PlateBox::kNumberRegion),
                       PlateDetection(6, {100, 100, 200, 150}, slam::PlateBox::kOutline)};
  const Json m = RunOne(world, truth, record, {frame, frame2});
  const Json& plates = m["detection"]["door_plate"];
  CHECK(plates["true_positives"] == 2);
  CHECK(plates["false_positives"] == 0);
  CHECK(Num(plates["mean_iou"]) == Approx(1.0).margin(test::kMetricsJsonRatio));

  // The same number-region box claimed to be an outline does not match the plate.
  record.detections = {PlateDetection(5, {120, 115, 180, 135}, slam::PlateBox::kOutline)};
  const Json wrong = RunOne(world, truth, record, {frame});
  CHECK(wrong["detection"]["door_plate"]["true_positives"] == 0);
  CHECK(wrong["detection"]["door_plate"]["false_positives"] == 1);
}

}  // namespace
}  // namespace corridorsim::metrics_tests
