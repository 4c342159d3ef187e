// Tests harness/metrics/association.cpp: data association precision and recall against each
// detection's identity. Each case is constructed so that its answer is known in closed form.
#include "harness/metrics/association.h"

#include <vector>

#include <catch2/catch.hpp>

#include "tests/harness/metrics/support.h"
#include "tests/support/tolerances.h"

namespace corridorsim::metrics_tests {
namespace {

slam::Detection PlateDetection(TimeNs stamp, const Vector2d& px, int landmark, bool created) {
  slam::Detection d = DetectionAt(stamp, "lateral", LandmarkType::kDoorPlate, px);
  d.landmark_id = landmark;
  d.new_landmark = created;
  return d;
}

TEST_CASE("data association precision and recall count one wrong association", "[metrics]") {
  const worlds::World world = PlateWorld();
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("da", truth, {"lateral"});
  record.landmarks = {Landmark(10, LandmarkType::kDoorPlate, {1, 1, 1.5}, "101"),
                      Landmark(20, LandmarkType::kDoorPlate, {4, 1, 1.5}, "102")};
  std::vector<FrameTruthSample> frames;
  for (const TimeNs t : {1, 2, 3}) {
    FrameTruthSample f = Frame("lateral", t);
    f.truth.plates = {PlateSeen(1, {100, 200}), PlateSeen(2, {400, 200})};
    frames.push_back(f);
  }
  record.detections = {
      PlateDetection(1, {101, 200}, 10, true),   // creates the landmark of plate 1
      PlateDetection(1, {399, 201}, 20, true),   // creates the landmark of plate 2
      PlateDetection(2, {102, 199}, 10, false),  // correct
      PlateDetection(2, {401, 200}, 10, false),  // wrong: plate 2 associated with plate 1's
      PlateDetection(3, {400, 202}, 20, false),  // correct
      PlateDetection(3, {99, 200}, -1, false),   // plate 1 not associated: a miss
      PlateDetection(3, {100, 201}, 99, false),  // a landmark not in the final map
  };
  const Json m = RunOne(world, truth, record, frames);
  REQUIRE(m.contains("data_association"));
  const Json& da = m["data_association"]["door_plate"];
  CheckCounts(da, {{"associations", 3}, {"correct", 2}, {"possible", 4}, {"unverifiable", 1}});
  CHECK(Num(da["precision"]) == Approx(2.0 / 3.0).margin(test::kMetricsJsonRatio));
  CHECK(Num(da["recall"]) == Approx(0.5).margin(test::kMetricsJsonRatio));
}

}  // namespace
}  // namespace corridorsim::metrics_tests
