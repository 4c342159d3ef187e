// Tests harness/metrics/map.cpp: landmarks matched one-to-one to ground truth; spurious, missed,
// errors. Each case is constructed so that its answer is known in closed form.
#include "harness/metrics/map.h"

#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/harness/metrics/support.h"
#include "tests/support/tolerances.h"

namespace corridorsim::metrics_tests {
namespace {

TEST_CASE("landmark matching counts a spurious and a missed landmark and wrong room numbers",
          "[metrics]") {
  const worlds::World world = PlateWorld();
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = Record("map", truth, [](const SE2& p) { return p; });
  record.cameras_used = {"lateral"};
  record.landmarks = {
      Landmark(10, LandmarkType::kDoorPlate, {1.1, 1.0, 1.4}, "101"),   // plate 1, 0.1 m off
      Landmark(11, LandmarkType::kDoorPlate, {4.0, 1.2, 1.5}, "999"),   // plate 2, wrong number
      Landmark(12, LandmarkType::kDoorPlate, {20.0, 0.0, 1.5}, "120"),  // nothing near: spurious
      // Two lamps near the one lamp: one-to-one leaves the farther one spurious.
      Landmark(20, LandmarkType::kLamp, {2.05, 0.0, 2.5}),
      Landmark(21, LandmarkType::kLamp, {2.3, 0.0, 2.4}),
  };
  FrameTruthSample frame = Frame("lateral", 0);
  for (int id = 1; id <= 3; ++id) frame.truth.plates.push_back(PlateSeen(id, {100.0 * id, 50}));
  const Json m = RunOne(world, truth, record, {frame});
  REQUIRE(m.contains("map"));
  const Json& plates = m["map"]["door_plate"];
  CHECK(plates["estimated"] == 3);
  CHECK(plates["matched"] == 2);
  CHECK(plates["spurious"] == 1);
  CHECK(plates["observed"] == 3);
  CHECK(plates["missed"] == 1);  // plate 3 was seen but never mapped
  CHECK(Num(plates["mean_error_m"]) == Approx(0.15).margin(test::kMetricsJsonM));
  CHECK(Num(plates["rmse_m"]) == Approx(std::sqrt(0.025)).margin(test::kMetricsJsonM));
  CHECK(Num(plates["max_error_m"]) == Approx(0.2).margin(test::kMetricsJsonM));
  CHECK(Num(plates["room_number_accuracy"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
  const Json& lamps = m["map"]["lamp"];
  CHECK(lamps["matched"] == 1);
  CHECK(lamps["spurious"] == 1);
  CHECK(lamps["observed"] == 0);  // no frame saw the lamp: it cannot be missed
  CHECK(lamps["missed"] == 0);
  CHECK(Num(lamps["mean_error_m"]) == Approx(0.05).margin(test::kMetricsJsonM));
  CHECK(Num(lamps["z_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
}

}  // namespace
}  // namespace corridorsim::metrics_tests

namespace corridorsim::metrics_tests {
namespace {

TEST_CASE(
    "a corner landmark is scored against the point its creating detection saw, not the "
    "nearest tile crossing",
    "[metrics]") {
  // A ceiling of tile crossings every 0.6 m: every estimate has one within the 1 m gate.
  worlds::World world;
  for (int i = 0; i < 20; ++i) {
    worlds::CornerPoint c;
    c.id = 100 + i;
    c.position = Eigen::Vector3d(0.6 * i, 0.0, 2.7);
    world.corner_points.push_back(c);
  }
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = Record("harris", truth, [](const SE2& p) { return p; });
  record.cameras_used = {"front"};
  const auto corner = [](int landmark_id) {
    slam::Detection d;
    d.stamp_ns = 5;
    d.camera_id = "front";
    d.type = LandmarkType::kCorner;
    d.pixel = Vector2d(100, 100);
    d.landmark_id = landmark_id;
    d.new_landmark = true;
    return d;
  };
  record.detections = {corner(1), corner(2)};
  // Landmark 1 saw a door-frame corner at (3.0, 1.1, 2.0) and is estimated 5 cm from it;
  // landmark 2 saw a point at (4.0, -1.1, 0.5) but is estimated 1.1 m away, on a tile
  // crossing (the old scheme would have matched it).
  record.seen_points[0] = SeenPoint{Eigen::Vector3d(3.0, 1.1, 2.0), 7};
  record.seen_points[1] = SeenPoint{Eigen::Vector3d(4.0, -1.1, 0.5), 8};
  record.landmarks = {Landmark(1, LandmarkType::kCorner, {3.05, 1.1, 2.0}),
                      Landmark(2, LandmarkType::kCorner, {4.2, 0.0, 2.7})};
  FrameTruthSample frame = Frame("front", 5);
  const Json m = RunOne(world, truth, record, {frame});
  const Json& corners = m["map"]["corner"];
  CHECK(corners["estimated"] == 2);
  CHECK(corners["matched"] == 1);
  CHECK(corners["spurious"] == 1);
  CHECK(Num(corners["mean_error_m"]) == Approx(0.05).margin(test::kMetricsJsonM));
  CHECK(Num(corners["z_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  CHECK(corners["observed"].is_null());
}

}  // namespace
}  // namespace corridorsim::metrics_tests
