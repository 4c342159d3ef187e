// Tests harness/metrics/expectations.cpp: parsing and checking the scenario expectations.
// Each case is constructed so that its answer is known in closed form.
#include "harness/metrics/expectations.h"

#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/harness/metrics/support.h"
#include "tests/support/tolerances.h"

namespace corridorsim::metrics_tests {
namespace {

// Each text must parse; the results of checking them all against `metrics`.
std::vector<ExpectationResult> ParseAndCheck(const Json& metrics,
                                             const std::vector<std::string>& texts) {
  std::vector<Expectation> expectations;
  for (const std::string& text : texts) {
    Expectation e;
    REQUIRE_FALSE(ParseExpectation(text, &e));
    expectations.push_back(e);
  }
  return CheckExpectations(metrics, expectations);
}

TEST_CASE("expectations parse '<pipeline>.<metric> <op> <number>' and reject the rest",
          "[metrics]") {
  Expectation e;
  REQUIRE_FALSE(ParseExpectation("p1_vp_doorplate.ate_rmse_m < 0.15", &e));
  CHECK(e.pipeline == "p1_vp_doorplate");
  CHECK(e.metric == "ate_rmse_m");
  CHECK(e.op == Expectation::Op::kLess);
  CHECK(e.value == 0.15);
  CHECK(e.text == "p1_vp_doorplate.ate_rmse_m < 0.15");
  REQUIRE_FALSE(ParseExpectation("p3.nis.lamp.mean>=0.5", &e));
  CHECK(e.metric == "nis.lamp.mean");
  CHECK(e.op == Expectation::Op::kGreaterEqual);
  CHECK(e.value == 0.5);
  // A pipeline's own measurement type's NIS (slam::MeasurementType), by any valid name, with the
  // fields the shipped types' NIS has.
  REQUIRE_FALSE(ParseExpectation("mine.nis.scan_match.mean < 2", &e));
  CHECK(e.metric == "nis.scan_match.mean");
  REQUIRE(ParseExpectation("mine.nis.scan_match.bogus < 2", &e));
  REQUIRE(ParseExpectation("mine.nis.Scan-Match.mean < 2", &e));

  const auto bad_op = ParseExpectation("p1.ate_rmse_m == 0.1", &e);
  REQUIRE(bad_op);
  CHECK_THAT(*bad_op, Catch::Contains("bad operator '=='"));
  REQUIRE(ParseExpectation("p1.ate_rmse_m =< 0.1", &e));
  const auto unknown = ParseExpectation("p1.ate_rmse < 0.1", &e);
  REQUIRE(unknown);
  CHECK_THAT(*unknown, Catch::Contains("unknown metric 'ate_rmse' (known: ") &&
                           Catch::Contains("ate_rmse_m"));
  const auto not_number = ParseExpectation("p1.ate_rmse_m < 0.1x", &e);
  REQUIRE(not_number);
  CHECK_THAT(*not_number, Catch::Contains("'0.1x' is not a number"));
  REQUIRE(ParseExpectation("p1.ate_rmse_m < nan", &e));
  REQUIRE(ParseExpectation("p1.ate_rmse_m <", &e));
  REQUIRE(ParseExpectation("ate_rmse_m < 1", &e));  // no pipeline
}

TEST_CASE("expectations pass, fail, and fail on a missing or null metric", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  MetricsInput input;
  input.world = &world;
  input.truth = truth;
  input.pipelines = {
      Record("offset", truth, [](const SE2& p) { return SE2(p.x() + 0.3, p.y() - 0.4, p.yaw()); }),
      // A zero covariance gives no NEES: nees_mean is null.
      Record(
          "no_cov", truth, [](const SE2& p) { return p; }, Matrix3d::Zero())};
  const Json metrics = ComputeMetrics(input);
  const std::vector<ExpectationResult> results = ParseAndCheck(
      metrics, {"offset.ate_rmse_m < 0.6", "offset.ate_rmse_m >= 0.6", "offset.nis.lamp.mean < 3",
                "absent.ate_rmse_m < 1", "no_cov.nees_mean < 10"});
  REQUIRE(results.size() == 5);
  CHECK(results[0].passed);
  CHECK(*results[0].measured == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK_FALSE(results[1].passed);
  CHECK(results[1].measured.has_value());
  for (std::size_t i = 2; i < 5; ++i) {
    INFO(results[i].expectation.text);
    CHECK_FALSE(results[i].passed);
    CHECK_FALSE(results[i].measured.has_value());
  }
}

TEST_CASE("a health counter written only when non-zero reads as 0 where it is absent",
          "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord broken = ExactRecord("broken", truth);
  broken.innovations.push_back({0, LandmarkType::kLamp, 1.0, 0, true, {}});  // no dof: malformed
  MetricsInput input;
  input.world = &world;
  input.truth = truth;
  input.pipelines = {broken, ExactRecord("clean", truth)};
  const std::vector<ExpectationResult> results =
      ParseAndCheck(ComputeMetrics(input), {"broken.health.malformed_innovations < 1",
                                            "clean.health.malformed_innovations < 1",
                                            "absent.health.malformed_innovations < 1"});
  REQUIRE(results.size() == 3);
  CHECK_FALSE(results[0].passed);
  CHECK(*results[0].measured == 1.0);
  CHECK(results[1].passed);
  CHECK(*results[1].measured == 0.0);
  CHECK_FALSE(results[2].passed);  // no such pipeline: missing
  CHECK_FALSE(results[2].measured.has_value());
}

}  // namespace
}  // namespace corridorsim::metrics_tests
