// Tests harness/metrics/registry.cpp: every metric declared once, the names expectations accept,
// rounding through the declared step, and docs/metrics.md's generated tables against the registry.
#include "harness/metrics/registry.h"

#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

using Json = nlohmann::ordered_json;
using metrics::FindMetric;
using metrics::MetricRegistry;
using metrics::MetricScope;
using metrics::MetricSpec;
using metrics::MetricUnit;
using metrics::MetricWriter;

TEST_CASE("MetricNames lists the pipeline scalars in the schema order expectations have used",
          "[metrics][registry]") {
  // The names before the registry (schema version 1), in their order, with the vanishing point's
  // hits, false positives and precision and the dense map's quality added since (P1), and the
  // lamp detector's rejections and border-cut lamps (P3);
  // the health counters that are written only when non-zero come after them.
  const std::vector<std::string> v1 = {
      "samples",
      "samples_without_truth",
      "distance_travelled_m",
      "ate_rmse_m",
      "ate_mean_m",
      "ate_max_m",
      "ate_yaw_rmse_rad",
      "ate_aligned_rmse_m",
      "ate_aligned_mean_m",
      "ate_aligned_max_m",
      "alignment.x_m",
      "alignment.y_m",
      "alignment.yaw_rad",
      "rpe_1m_trans_rmse_m",
      "rpe_1m_yaw_rmse_rad",
      "rpe_1m_pairs",
      "rpe_5m_trans_rmse_m",
      "rpe_5m_yaw_rmse_rad",
      "rpe_5m_pairs",
      "rpe_10m_trans_rmse_m",
      "rpe_10m_yaw_rmse_rad",
      "rpe_10m_pairs",
      "final_position_error_m",
      "final_yaw_error_rad",
      "nees_samples",
      "nees_skipped",
      "nees_mean",
      "nees_in_band_fraction",
      "nees_final",
      "nis.door_plate.count",
      "nis.door_plate.gated",
      "nis.door_plate.mean",
      "nis.door_plate.in_band_fraction",
      "nis.door_plate.mean_band_low",
      "nis.door_plate.mean_band_high",
      "nis.corner.count",
      "nis.corner.gated",
      "nis.corner.mean",
      "nis.corner.in_band_fraction",
      "nis.corner.mean_band_low",
      "nis.corner.mean_band_high",
      "nis.lamp.count",
      "nis.lamp.gated",
      "nis.lamp.mean",
      "nis.lamp.in_band_fraction",
      "nis.lamp.mean_band_low",
      "nis.lamp.mean_band_high",
      "nis.door.count",
      "nis.door.gated",
      "nis.door.mean",
      "nis.door.in_band_fraction",
      "nis.door.mean_band_low",
      "nis.door.mean_band_high",
      "nis.vanishing_point.count",
      "nis.vanishing_point.gated",
      "nis.vanishing_point.mean",
      "nis.vanishing_point.in_band_fraction",
      "nis.vanishing_point.mean_band_low",
      "nis.vanishing_point.mean_band_high",
      "map.door_plate.estimated",
      "map.door_plate.matched",
      "map.door_plate.spurious",
      "map.door_plate.observed",
      "map.door_plate.missed",
      "map.door_plate.mean_error_m",
      "map.door_plate.rmse_m",
      "map.door_plate.max_error_m",
      "map.door_plate.room_number_accuracy",
      "map.corner.estimated",
      "map.corner.matched",
      "map.corner.spurious",
      "map.corner.observed",
      "map.corner.missed",
      "map.corner.mean_error_m",
      "map.corner.rmse_m",
      "map.corner.max_error_m",
      "map.corner.z_rmse_m",
      "map.lamp.estimated",
      "map.lamp.matched",
      "map.lamp.spurious",
      "map.lamp.observed",
      "map.lamp.missed",
      "map.lamp.mean_error_m",
      "map.lamp.rmse_m",
      "map.lamp.max_error_m",
      "map.lamp.z_rmse_m",
      "map.door.estimated",
      "map.door.matched",
      "map.door.spurious",
      "map.door.observed",
      "map.door.missed",
      "map.door.mean_error_m",
      "map.door.rmse_m",
      "map.door.max_error_m",
      "map.door.open_registered",  // P3's door scoring (issue 16), added since
      "map.door.closed_registered",
      "map.door.non_door_registered",
      "map.door.duplicates",
      "map.door.open_seen",
      "map.door.open_found",
      "map.door.open_precision",
      "map.door.open_recall",
      "map.door.open_column_rmse_m",
      "map.occupancy.resolution_m",
      "map.occupancy.occupied_voxels",
      "map.occupancy.truth_observed",
      "map.occupancy.precision",
      "map.occupancy.recall",
      "map.area.rooms",  // P2 Fig. 12's areas (issue 16), added since
      "map.area.rooms_behind_open_doors",
      "map.area.landmarks_scored",
      "map.area.in_unregistered_room",
      "map.area.assigned_correctly",
      "map.area.assignment_accuracy",
      "map.area.room_landmarks",
      "map.area.room_landmarks_found",
      "data_association.door_plate.associations",
      "data_association.door_plate.correct",
      "data_association.door_plate.possible",
      "data_association.door_plate.unverifiable",
      "data_association.door_plate.precision",
      "data_association.door_plate.recall",
      "data_association.corner.associations",
      "data_association.corner.correct",
      "data_association.corner.possible",
      "data_association.corner.unverifiable",
      "data_association.corner.precision",
      "data_association.corner.recall",
      "data_association.lamp.associations",
      "data_association.lamp.correct",
      "data_association.lamp.possible",
      "data_association.lamp.unverifiable",
      "data_association.lamp.precision",
      "data_association.lamp.recall",
      "data_association.door.associations",
      "data_association.door.correct",
      "data_association.door.possible",
      "data_association.door.unverifiable",
      "data_association.door.precision",
      "data_association.door.recall",
      "detection.vanishing_point.count",
      "detection.vanishing_point.without_truth",
      "detection.vanishing_point.hits",
      "detection.vanishing_point.false_positives",
      "detection.vanishing_point.mean_error_px",
      "detection.vanishing_point.rmse_error_px",
      "detection.vanishing_point.mean_abs_u_error_px",
      "detection.vanishing_point.precision",
      "detection.vanishing_point.detected_frame_fraction",
      "detection.door_plate.detections",
      "detection.door_plate.true_positives",
      "detection.door_plate.false_positives",
      "detection.door_plate.false_negatives",
      "detection.door_plate.ignored",
      "detection.door_plate.without_truth",
      "detection.door_plate.precision",
      "detection.door_plate.recall",
      "detection.lamp.detections",
      "detection.lamp.true_positives",
      "detection.lamp.false_positives",
      "detection.lamp.false_negatives",
      "detection.lamp.ignored",
      "detection.lamp.without_truth",
      "detection.lamp.precision",
      "detection.lamp.recall",
      "detection.door.detections",
      "detection.door.true_positives",
      "detection.door.false_positives",
      "detection.door.false_negatives",
      "detection.door.ignored",
      "detection.door.without_truth",
      "detection.door.precision",
      "detection.door.recall",
      "detection.door_plate.mean_iou",
      "detection.door_plate.room_number_read_fraction",
      "detection.door_plate.room_number_accuracy",
      "detection.lamp.mean_center_error_px",
      "detection.lamp.rmse_center_error_px",
      "detection.lamp.max_center_error_px",  // P3's scoring (issue 16), added since
      "detection.lamp.to_reject",
      "detection.lamp.rejected",
      "detection.lamp.rejected_fraction",
      "detection.lamp.border_cut",
      "detection.lamp.border_cut_found",
      "detection.lamp.border_cut_max_center_error_px",
      "detection.door.open_state_accuracy",
      "timing.frames",
      "timing.steps",
      "timing.total_ms_per_frame",
      "timing.total_ms_per_step",
      "health.non_positive_covariance",
      "health.rejected_updates",
  };
  const std::vector<std::string> names = MetricNames();
  REQUIRE(names.size() == v1.size() + 8);
  CHECK(std::vector<std::string>(names.begin(), names.begin() + static_cast<long>(v1.size())) ==
        v1);
  CHECK(names[v1.size()] == "health.rejected_odometry");
  CHECK(names[v1.size() + 1] == "health.rejected_frames");
  CHECK(names[v1.size() + 2] == "health.malformed_innovations");
  CHECK(names[v1.size() + 3] == "health.non_finite_covariances");
  CHECK(names[v1.size() + 4] == "health.non_finite_estimates");
  CHECK(names[v1.size() + 5] == "timing.cpu_ms_per_frame");
  CHECK(names[v1.size() + 6] == "timing.cpu_seconds");
  CHECK(names[v1.size() + 7] == "health.failed");
}

TEST_CASE("every metric is declared once with a unit, a step and a meaning",
          "[metrics][registry]") {
  std::set<std::pair<MetricScope, std::string>> paths;
  for (const MetricSpec& spec : MetricRegistry()) {
    INFO(spec.path);
    CHECK(paths.emplace(spec.scope, spec.path).second);
    CHECK_FALSE(spec.meaning.empty());
    CHECK_FALSE(spec.section.empty());
    CHECK(spec.path.find('<') == std::string::npos);  // placeholders expanded
    CHECK(metrics::StepsPerUnit(spec.unit) >= 1.0);
    CHECK(FindMetric(spec.scope, spec.path) == &spec);
  }
  const MetricSpec* z = FindMetric(MetricScope::kPipeline, "map.corner.z_rmse_m");
  REQUIRE(z != nullptr);
  CHECK(z->pattern == "map.<type>.z_rmse_m");
  CHECK(z->unit == MetricUnit::kMetres);
  // Declared for corners and lamps only.
  CHECK(FindMetric(MetricScope::kPipeline, "map.door.z_rmse_m") == nullptr);
  CHECK(FindMetric(MetricScope::kPipeline, "timing.stage_seconds.*")->map);
  CHECK(FindMetric(MetricScope::kRun, "run.sim_seconds") != nullptr);
  CHECK(FindMetric(MetricScope::kPipeline, "run.sim_seconds") == nullptr);
}

TEST_CASE("the writer rounds to the declared step and writes nested objects in call order",
          "[metrics][registry]") {
  Json object;
  const MetricWriter out(object, MetricScope::kPipeline);
  out.Set("ate_rmse_m", 0.12345649);                              // metres: 1e-6
  out.Set("ate_yaw_rmse_rad", 0.1234567849);                      // rad: 1e-8
  out.Set("alignment.x_m", -4e-7);                                // rounds to 0, without a sign
  out.Sub("nis").Sub("lamp").Fraction("in_band_fraction", 1, 3);  // ratio: 1e-6
  out.Sub("nis").Sub("lamp").Fraction("mean", 1, 0);              // null
  out.Set("ate_max_m", std::optional<double>());                  // null
  out.Sub("timing").Set("total_ms_per_step", 1.23456);            // ms: 1e-4
  out.Sub("timing").Map("stage_seconds");
  out.Sub("health").Count("non_positive_covariance", 0);
  out.Sub("health").Count("malformed_innovations", 0);  // absent when zero
  CHECK(object.dump() ==
        "{\"ate_rmse_m\":0.123456,\"ate_yaw_rmse_rad\":0.12345678,\"alignment\":{\"x_m\":0.0},"
        "\"nis\":{\"lamp\":{\"in_band_fraction\":0.333333,\"mean\":null}},\"ate_max_m\":null,"
        "\"timing\":{\"total_ms_per_step\":1.2346,\"stage_seconds\":{}},"
        "\"health\":{\"non_positive_covariance\":0}}");
  out.Sub("health").Count("malformed_innovations", 2);
  CHECK(object["health"]["malformed_innovations"] == 2);
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  REQUIRE(in.good());
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

TEST_CASE(
    "docs/metrics.md's metric tables are the registry's (corridorsim_docs --write docs updates "
    "them)",
    "[metrics][registry]") {
  const std::string docs = ReadFile(std::string(CORRIDORSIM_SOURCE_DIR) + "/docs/metrics.md");
  const std::string updated = metrics::UpdateMetricsDocs(docs);
  INFO("regenerate with: build/bin/corridorsim_docs --write docs");
  CHECK(updated == docs);
  // Every declared pattern stands in the docs.
  for (const MetricSpec& spec : MetricRegistry()) {
    INFO(spec.pattern);
    CHECK(docs.find("`" + spec.pattern + "`") != std::string::npos);
  }
}

TEST_CASE("the docs update refuses a missing or unknown block", "[metrics][registry]") {
  std::string blocks;
  for (const std::string& section : metrics::MetricsDocsSections()) {
    blocks += "<!-- BEGIN metrics-table " + section + " -->\nstale row\n<!-- END metrics-table " +
              section + " -->\n";
  }
  const std::string updated = metrics::UpdateMetricsDocs("intro\n" + blocks);
  CHECK(updated.find("stale row") == std::string::npos);
  CHECK(updated.find("| `samples` | count | 1 |") != std::string::npos);
  CHECK(updated.find("| `ate_rmse_m` | m | 1e-6 |") != std::string::npos);
  CHECK_THROWS_WITH(metrics::UpdateMetricsDocs("intro\n"), Catch::Contains("no block"));
  CHECK_THROWS_WITH(
      metrics::UpdateMetricsDocs(
          blocks + "<!-- BEGIN metrics-table nope -->\n<!-- END metrics-table nope -->\n"),
      Catch::Contains("unknown section 'nope'"));
}

}  // namespace
}  // namespace corridorsim
