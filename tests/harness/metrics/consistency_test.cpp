// Tests harness/metrics/consistency.cpp: NEES of the pose and NIS per landmark type against their
// chi-square bands, and the error series CSV. Each case is constructed so that its answer is known
// in closed form.
#include "harness/metrics/consistency.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>

#include "common/random.h"

#include <catch2/catch.hpp>

#include "tests/harness/metrics/support.h"
#include "tests/support/tolerances.h"

namespace corridorsim::metrics_tests {
namespace {

// Estimates whose errors are drawn from `covariance_k` (x, y, yaw), reported with
// covariance_k * reported_scale.
PipelineRecord DrawnEstimates(const std::vector<TruthPose>& truth, double reported_scale) {
  RandomStream random(7, 0, "tests.metrics.nees");
  PipelineRecord record;
  record.name = "drawn";
  for (std::size_t k = 0; k < truth.size(); k += 2) {
    // A covariance that changes along the run: its x-y axes turn with the robot.
    const double yaw = truth[k].world_from_robot.yaw();
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    rotation.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(yaw).toRotationMatrix();
    const double grow = 1.0 + 0.001 * static_cast<double>(k);
    const Vector3d sigma(0.2 * grow, 0.05 * grow, 0.03);
    const Matrix3d covariance = rotation * sigma.cwiseAbs2().asDiagonal() * rotation.transpose();
    const Matrix3d l = covariance.llt().matrixL();
    const Vector3d z(random.Normal(), random.Normal(), random.Normal());
    const Vector3d e = l * z;
    const SE2& t = truth[k].world_from_robot;
    record.estimates.push_back({truth[k].stamp_ns,
                                SE2(t.x() + e.x(), t.y() + e.y(), t.yaw() + e.z()),
                                covariance * reported_scale});
  }
  return record;
}

TEST_CASE("NEES of errors drawn from the covariance lands in band; an overconfident one does not",
          "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(40.0);
  const PipelineRecord drawn = DrawnEstimates(truth, 1.0);
  const Json good = RunOne(world, truth, drawn);
  const double n = good["nees_samples"].get<double>();
  REQUIRE(n == 2001);
  CHECK(good["nees_skipped"] == 0);
  // These draws are independent (a filter's are not, so metrics.json carries no band of the
  // mean): here the mean lies in chi2(3N) / N's two-sided 95 % band.
  const boost::math::chi_squared_distribution<double> mean_dist(3 * n);
  CHECK(Num(good["nees_mean"]) >= boost::math::quantile(mean_dist, 0.025) / n);
  CHECK(Num(good["nees_mean"]) <= boost::math::quantile(mean_dist, 0.975) / n);
  CHECK_FALSE(good.contains("nees_mean_band_low"));
  CHECK_FALSE(good.contains("nees_mean_band_high"));
  // nees_final: the NEES of the last sample, one chi2(3) draw.
  const EstimateSample& last = drawn.estimates.back();
  const auto last_truth = std::find_if(
      truth.begin(), truth.end(), [&](const TruthPose& t) { return t.stamp_ns == last.stamp_ns; });
  REQUIRE(last_truth != truth.end());
  const std::optional<double> last_nees = metrics::Nees(
      metrics::PoseError(last.world_from_robot, last_truth->world_from_robot), last.covariance);
  REQUIRE(last_nees);
  CHECK(Num(good["nees_final"]) == Approx(*last_nees).margin(test::kMetricsJsonRatio));
  // About 95 % of the samples inside the per-sample interval (binomial bound).
  const double z = boost::math::quantile(boost::math::normal(), 0.5 + test::kStatConfidence / 2);
  const double bound = z * std::sqrt(0.95 * 0.05 / n);
  CHECK(Num(good["nees_in_band_fraction"]) == Approx(0.95).margin(bound));

  const Json overconfident = RunOne(world, truth, DrawnEstimates(truth, 0.25));
  CHECK(Num(overconfident["nees_mean"]) > boost::math::quantile(mean_dist, 0.975) / n);
  CHECK(Num(overconfident["nees_in_band_fraction"]) < 0.95 - bound);
}

TEST_CASE("NIS is reported per landmark type over the accepted updates", "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("nis", truth);
  // Lamps, 2 dof: 1, 2, 3 accepted (inside [0.0506, 7.38]), 0.01 accepted (below), 50 gated.
  for (const double nis : {1.0, 2.0, 3.0, 0.01}) {
    record.innovations.push_back({0, LandmarkType::kLamp, nis, 2, true, {}});
  }
  record.innovations.push_back({0, LandmarkType::kLamp, 50.0, 2, false, {}});
  // Doors, 1 dof: one above the interval (5.02).
  record.innovations.push_back({0, LandmarkType::kDoor, 6.0, 1, true, {}});
  const Json m = RunOne(world, truth, record);
  REQUIRE(m.contains("nis"));
  const Json& lamp = m["nis"]["lamp"];
  CHECK(lamp["count"] == 4);
  CHECK(lamp["gated"] == 1);
  CHECK(Num(lamp["mean"]) == Approx(6.01 / 4).margin(test::kMetricsJsonRatio));
  CHECK(Num(lamp["in_band_fraction"]) == Approx(0.75).margin(test::kMetricsJsonRatio));
  const boost::math::chi_squared_distribution<double> lamp_mean(8);  // 4 updates x 2 dof
  CHECK(Num(lamp["mean_band_low"]) ==
        Approx(boost::math::quantile(lamp_mean, 0.025) / 4).margin(test::kMetricsJsonRatio));
  CHECK(Num(lamp["mean_band_high"]) ==
        Approx(boost::math::quantile(lamp_mean, 0.975) / 4).margin(test::kMetricsJsonRatio));
  const Json& door = m["nis"]["door"];
  CHECK(door["count"] == 1);
  CHECK(Num(door["in_band_fraction"]) == 0.0);
  CHECK_FALSE(m["nis"].contains("corner"));
}

TEST_CASE("a pipeline's own measurement types get NIS after the landmark types, by name",
          "[metrics]") {
  const worlds::World world;
  const std::vector<TruthPose> truth = ArcTruth(1.0);
  PipelineRecord record = ExactRecord("nis", truth);
  // A type named like none of the shipped ones, with a `type` field that must be ignored.
  record.innovations.push_back({0, LandmarkType::kLamp, 4.0, 3, true, "scan_match"});
  record.innovations.push_back({0, LandmarkType::kLamp, 2.0, 3, true, "scan_match"});
  record.innovations.push_back({0, LandmarkType::kLamp, 9.0, 1, false, "gyro_bias"});
  record.innovations.push_back({0, LandmarkType::kDoor, 1.0, 1, true, {}});
  const Json m = RunOne(world, truth, record);
  REQUIRE(m.contains("nis"));
  std::vector<std::string> order;
  for (const auto& [name, value] : m["nis"].items()) order.push_back(name);
  CHECK(order == std::vector<std::string>{"door", "gyro_bias", "scan_match"});
  CHECK_FALSE(m["nis"].contains("lamp"));
  const Json& scan = m["nis"]["scan_match"];
  CHECK(scan["count"] == 2);
  CHECK(Num(scan["mean"]) == Approx(3.0).margin(test::kMetricsJsonRatio));
  const boost::math::chi_squared_distribution<double> scan_mean(6);  // 2 updates x 3 dof
  CHECK(Num(scan["mean_band_high"]) ==
        Approx(boost::math::quantile(scan_mean, 0.975) / 2).margin(test::kMetricsJsonRatio));
  CHECK(m["nis"]["gyro_bias"]["count"] == 0);
  CHECK(m["nis"]["gyro_bias"]["gated"] == 1);
  CHECK(m["nis"]["gyro_bias"]["mean"].is_null());
  // The per-update file names the type too.
  const std::string csv = NisSeriesCsv(record);
  CHECK(csv.find(",scan_match,3,4.000000,1\n") != std::string::npos);
  CHECK(csv.find(",door,1,1.000000,1\n") != std::string::npos);
}

TEST_CASE("the error series CSV has one row per estimate with errors, sigmas and NEES",
          "[metrics]") {
  const std::vector<TruthPose> truth = {
      {0, SE2(0.0, 0.0, 0.0)}, {kGridNs, SE2(1.0, 0.0, 0.2)}, {2 * kGridNs, SE2(2.0, 0.0, 0.4)}};
  PipelineRecord record;
  record.name = "csv";
  // At the start with a zero covariance (no NEES), then between grid points (truth interpolated:
  // x 1.5, yaw 0.3), then after the truth ends (no row).
  record.estimates.push_back({0, SE2(0.0, 0.0, 0.0), Matrix3d::Zero()});
  const Matrix3d covariance = Vector3d(0.04, 0.09, 0.01).asDiagonal();
  record.estimates.push_back({kGridNs + kGridNs / 2, SE2(1.6, -0.2, 0.35), covariance});
  record.estimates.push_back({3 * kGridNs, SE2(3.0, 0.0, 0.6), covariance});
  const std::string csv = ErrorSeriesCsv(truth, record);
  CHECK(csv ==
        "t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n"
        "0.000000000,0.000000,0.000000,0.00000000,0.000000,0.000000,0.00000000,\n"
        // NEES = 0.1^2/0.04 + 0.2^2/0.09 + 0.05^2/0.01
        "0.015000000,0.100000,-0.200000,0.05000000,0.200000,0.300000,0.10000000,0.944444\n");
}

TEST_CASE("the error series CSV leaves a value that is not finite empty, never nan", "[metrics]") {
  const std::vector<TruthPose> truth = {
      {0, SE2(0.0, 0.0, 0.0)}, {kGridNs, SE2(1.0, 0.0, 0.2)}, {2 * kGridNs, SE2(2.0, 0.0, 0.4)}};
  PipelineRecord record;
  record.name = "csv";
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  // Covariances with NaN and infinite variances: no sigma there, no NEES. (Estimates that are
  // not finite have no row: MatchToTruth counts and skips them.)
  record.estimates.push_back({0, SE2(0.1, 0.0, 0.0), Vector3d(0.04, nan, inf).asDiagonal()});
  record.estimates.push_back({kGridNs, SE2(1.0, 0.1, 0.2), Vector3d(0.04, 0.09, nan).asDiagonal()});
  const std::string csv = ErrorSeriesCsv(truth, record);
  CHECK(csv ==
        "t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n"
        "0.000000000,0.100000,0.000000,0.00000000,0.200000,,,\n"
        "0.010000000,0.000000,0.100000,0.00000000,0.200000,0.300000,,\n");
  CHECK(csv.find("nan") == std::string::npos);
  CHECK(csv.find("inf") == std::string::npos);
}

}  // namespace
}  // namespace corridorsim::metrics_tests
