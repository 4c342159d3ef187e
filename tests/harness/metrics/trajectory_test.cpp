// Tests harness/metrics/trajectory.cpp: ATE unaligned and aligned, RPE over distance, the final
// error. Each case is constructed so that its answer is known in closed form.
#include "harness/metrics/trajectory.h"

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "tests/harness/metrics/support.h"
#include "tests/support/tolerances.h"

namespace corridorsim::metrics_tests {
namespace {

TEST_CASE("identical trajectories give zero errors", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  const Json m = RunOne(world, truth, ExactRecord("same", truth));
  CHECK(m["samples"] == 1001);
  CHECK(m["samples_without_truth"] == 0);
  CHECK(Num(m["distance_travelled_m"]) == Approx(20.0).margin(test::kMetricsJsonM));
  for (const char* key :
       {"ate_rmse_m", "ate_mean_m", "ate_max_m", "ate_aligned_rmse_m", "ate_aligned_max_m",
        "rpe_1m_trans_rmse_m", "rpe_10m_trans_rmse_m", "final_position_error_m"}) {
    INFO(key);
    CHECK(Num(m[key]) == 0.0);
  }
  CHECK(Num(m["ate_yaw_rmse_rad"]) == 0.0);
  CHECK(Num(m["rpe_5m_yaw_rmse_rad"]) == 0.0);
  CHECK(m["rpe_10m_pairs"].get<int>() > 0);
  CHECK(Num(m["nees_mean"]) == 0.0);
  // Nothing to map, no innovations, no frames: those metrics are absent, never invented.
  CHECK_FALSE(m.contains("map"));
  CHECK_FALSE(m.contains("nis"));
  CHECK_FALSE(m.contains("data_association"));
  CHECK_FALSE(m.contains("detection"));
  CHECK(m["timing"]["total_ms_per_frame"].is_null());
  CHECK(m["timing"]["cpu_ms_per_frame"].is_null());
}

TEST_CASE("a constant offset gives that ATE unaligned and none aligned", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  const Json m = RunOne(world, truth, Record("offset", truth, [](const SE2& p) {
                          return SE2(p.x() + 0.3, p.y() - 0.4, p.yaw());
                        }));
  CHECK(Num(m["ate_rmse_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["ate_mean_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["ate_max_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["final_position_error_m"]) == Approx(0.5).margin(test::kMetricsJsonM));
  CHECK(Num(m["ate_aligned_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  CHECK(Num(m["alignment"]["x_m"]) == Approx(-0.3).margin(test::kMetricsJsonM));
  CHECK(Num(m["alignment"]["y_m"]) == Approx(0.4).margin(test::kMetricsJsonM));
  CHECK(Num(m["alignment"]["yaw_rad"]) == Approx(0.0).margin(test::kMetricsJsonRad));
  // A translation does not change any relative motion.
  CHECK(Num(m["rpe_1m_trans_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
}

TEST_CASE("a rotated and translated copy aligns to zero error", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(20.0);
  const SE2 copy_from_truth(2.0, -1.0, 0.7);
  const Json m = RunOne(world, truth,
                        Record("moved", truth, [&](const SE2& p) { return copy_from_truth * p; }));
  CHECK(Num(m["ate_rmse_m"]) > 1.0);
  CHECK(Num(m["ate_aligned_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  CHECK(Num(m["ate_aligned_max_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  const SE2 truth_from_copy = copy_from_truth.Inverse();
  CHECK(Num(m["alignment"]["yaw_rad"]) ==
        Approx(truth_from_copy.yaw()).margin(test::kMetricsJsonRad));
  CHECK(Num(m["alignment"]["x_m"]) == Approx(truth_from_copy.x()).margin(test::kMetricsJsonM));
  CHECK(Num(m["alignment"]["y_m"]) == Approx(truth_from_copy.y()).margin(test::kMetricsJsonM));
  // A rigid motion of the whole trajectory leaves relative motions unchanged.
  CHECK(Num(m["rpe_5m_trans_rmse_m"]) == Approx(0.0).margin(test::kMetricsJsonM));
  CHECK(Num(m["rpe_5m_yaw_rmse_rad"]) == Approx(0.0).margin(test::kMetricsJsonRad));
}

TEST_CASE("RPE of a heading drift grows with the distance as the drift's arc", "[metrics]") {
  // Truth drives straight along x; the estimate turns at drift_rad_per_m (a constant-curvature
  // arc), so over any d metres its relative motion is the arc's chord and turn.
  const worlds::World world;
  const double drift_rad_per_m = 0.01;
  const double step_m = 0.25;  // exact in binary: truth distances sum exactly
  std::vector<TruthPose> truth;
  PipelineRecord record;
  record.name = "drift";
  for (int k = 0; k <= 100; ++k) {
    const double s_m = step_m * k;
    truth.push_back({k * kGridNs, SE2(s_m, 0.0, 0.0)});
    const double yaw = drift_rad_per_m * s_m;
    record.estimates.push_back(
        {k * kGridNs,
         SE2(std::sin(yaw) / drift_rad_per_m, (1.0 - std::cos(yaw)) / drift_rad_per_m, yaw),
         Matrix3d::Identity()});
  }
  const Json m = RunOne(world, truth, record);
  for (const int d : {1, 5, 10}) {
    INFO("d = " << d);
    const double turn = drift_rad_per_m * d;
    const double along = std::sin(turn) / drift_rad_per_m - d;
    const double across = (1.0 - std::cos(turn)) / drift_rad_per_m;
    const std::string prefix = "rpe_" + std::to_string(d) + "m_";
    CHECK(Num(m[prefix + "yaw_rmse_rad"]) == Approx(turn).margin(test::kMetricsJsonRad));
    CHECK(Num(m[prefix + "trans_rmse_m"]) ==
          Approx(std::hypot(along, across)).margin(test::kMetricsJsonM));
    // Every start sample with d metres of truth after it.
    CHECK(m[prefix + "pairs"] == 101 - static_cast<int>(d / step_m));
  }
}

}  // namespace
}  // namespace corridorsim::metrics_tests

namespace corridorsim {
namespace {

TEST_CASE("PoseAsWritten gives back what the run's TUM line says", "[metrics]") {
  const SE2 pose(1.23456789, -2.0000004, 2.9);
  const SE2 written = metrics::PoseAsWritten(pose);
  // x, y: the file's six decimals, parsed; yaw: 2 atan2(qz, qw) of the nine-decimal quaternion.
  CHECK(written.x() == 1.234568);
  CHECK(written.y() == -2.0);
  char text[64];
  std::snprintf(text, sizeof(text), "%.9f %.9f", std::sin(2.9 / 2), std::cos(2.9 / 2));
  double z = 0.0, w = 0.0;
  REQUIRE(std::sscanf(text, "%lf %lf", &z, &w) == 2);
  CHECK(written.yaw() == NormalizeAngle(2.0 * std::atan2(z, w)));
  CHECK(std::abs(written.yaw() - 2.9) < 1e-8);
  // A NaN stays NaN (the line says "nan"; the metrics count it as non-finite).
  CHECK(std::isnan(metrics::PoseAsWritten(SE2(std::nan(""), 0.0, 0.0)).x()));
}

}  // namespace
}  // namespace corridorsim
