// Tests harness/metrics/compute.cpp: the composition of metrics.json, the run section, and a
// pipeline's malformed output (an innovation without degrees of freedom, a NaN covariance or
// pose) counted in its health and reported, never aborting the run.
#include "harness/metrics/compute.h"

#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/harness/metrics/support.h"
#include "tests/support/tolerances.h"

namespace corridorsim::metrics_tests {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST_CASE("the run section reports wall times and their fractions only when given", "[metrics]") {
  const worlds::World world;
  MetricsInput input;
  input.world = &world;
  input.timing.sim_seconds = 12.0;
  Json m = ComputeMetrics(input);
  CHECK(m.dump() ==
        "{\"schema_version\":1,\"run\":{\"sim_seconds\":12.0,\"wall_seconds\":{},"
        "\"wall_total_s\":0.0,\"real_time_factor\":null},"
        "\"frames\":{\"count\":0,\"per_camera\":{}},\"pipelines\":{}}");
  input.timing.wall_seconds = {{"physics", 1.0}, {"rendering", 3.0}};
  m = ComputeMetrics(input);
  CHECK(Num(m["run"]["wall_total_s"]) == 4.0);
  CHECK(Num(m["run"]["real_time_factor"]) == 3.0);
  CHECK(Num(m["run"]["wall_fraction"]["rendering"]) == 0.75);
}

TEST_CASE("a healthy pipeline's health holds the pipeline's own counters only", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("healthy", truth);
  record.health.non_positive_covariance = 2;
  record.health.rejected_updates = 3;
  const Json m = RunOne(world, truth, record);
  CHECK(m["health"].dump() == "{\"non_positive_covariance\":2,\"rejected_updates\":3}");
}

TEST_CASE("malformed pipeline output is counted in health and reported, never aborts",
          "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("broken", truth);
  const std::size_t estimates = record.estimates.size();
  // A NaN covariance (kept: no NEES) and a NaN pose (left out of the trajectory metrics).
  record.estimates[10].covariance(1, 1) = kNaN;
  record.estimates[20].world_from_robot = SE2(kNaN, 0.0, 0.0);
  // Innovations: one good lamp update, one with dof 0, one with a NaN and one with a negative NIS.
  record.innovations.push_back({0, LandmarkType::kLamp, 1.0, 2, true, {}});
  record.innovations.push_back({0, LandmarkType::kLamp, 1.0, 0, true, {}});
  record.innovations.push_back({0, LandmarkType::kLamp, kNaN, 2, true, {}});
  record.innovations.push_back({0, LandmarkType::kDoor, -1.0, 1, false, {}});

  const Json m = RunOne(world, truth, record);
  const Json& health = m["health"];
  CHECK(health["malformed_innovations"] == 3);
  CHECK(health["non_finite_covariances"] == 1);
  CHECK(health["non_finite_estimates"] == 1);
  CHECK(m["samples"] == estimates - 1);
  CHECK(m["nees_skipped"] == 1);
  CHECK(m["nees_samples"] == estimates - 2);
  CHECK(Num(m["ate_max_m"]) == 0.0);  // the NaN pose is not in the errors
  CHECK(m["nis"]["lamp"]["count"] == 1);
  CHECK(m["nis"]["lamp"]["gated"] == 0);
  CHECK(Num(m["nis"]["lamp"]["mean"]) == 1.0);
  CHECK_FALSE(m["nis"].contains("door"));  // its only update was malformed
  // Reported as metrics.json writes it.
  CHECK_THAT(health.dump(),
             Catch::EndsWith("\"malformed_innovations\":3,\"non_finite_covariances\":1,"
                             "\"non_finite_estimates\":1}"));
}

}  // namespace
}  // namespace corridorsim::metrics_tests
