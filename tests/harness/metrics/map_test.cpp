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
