#pragma once
// The metric registry: every metric of metrics.json is declared once, with its dotted path, unit,
// rounding step and a one-line meaning, in the table registry.def. The values are written through
// it (MetricWriter rounds with the declared step and refuses a path nobody declared),
// MetricNames() lists its pipeline scalars, and the metric tables of docs/metrics.md are generated
// from it (UpdateMetricsDocs; a unit test fails when the docs and the registry disagree).

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "slam/pipeline.h"

namespace corridorsim {

/// Every scalar metric name a pipeline can have, in schema order (the names expectations accept).
std::vector<std::string> MetricNames();

/// Every scalar metric name an estimate of `corridorsim evaluate` can have (what its --expect
/// accepts): the trajectory, nees and map metrics of a pipeline, then the evaluation's own.
std::vector<std::string> EvaluationMetricNames();

namespace metrics {

// Landmark types in schema order; vanishing points have no position in the world (no map, no
// association), only a detector error.
inline constexpr slam::LandmarkType kAllTypes[] = {
    slam::LandmarkType::kDoorPlate, slam::LandmarkType::kCorner, slam::LandmarkType::kLamp,
    slam::LandmarkType::kDoor, slam::LandmarkType::kVanishingPoint};
inline constexpr slam::LandmarkType kMapTypes[] = {
    slam::LandmarkType::kDoorPlate, slam::LandmarkType::kCorner, slam::LandmarkType::kLamp,
    slam::LandmarkType::kDoor};
// RPE: relative motions over these truth distances (m).
inline constexpr int kRpeDistancesM[] = {1, 5, 10};

/// A unit and the rounding step its values are written with (common/io/stable_json.h).
enum class MetricUnit { kCount, kMetres, kRad, kPx, kRatio, kSeconds, kMs };
std::string_view MetricUnitName(MetricUnit unit);  // "count", "m", "rad", "px", "ratio", "s", "ms"
double StepsPerUnit(MetricUnit unit);              // values are multiples of 1 / steps; counts 1

/// Where a metric lives in metrics.json.
enum class MetricScope {
  kRun,       // under the file's root: run.*, frames.*
  kPipeline,  // under pipelines.<name>; the scalars are what expectations may name
  // under estimates.<name> of `corridorsim evaluate`'s evaluation.json, beside the trajectory,
  // nees and map metrics of kPipeline (EvaluationMetricNames)
  kEvaluation,
};

struct MetricSpec {
  std::string path;     // dotted, under the scope's object; a map's entries end in ".*"
  std::string pattern;  // as declared, e.g. "map.<type>.z_rmse_m" (the docs show this)
  MetricUnit unit = MetricUnit::kCount;
  std::string meaning;  // one line
  std::string section;  // the docs table that lists it
  MetricScope scope = MetricScope::kPipeline;
  bool map = false;  // an object keyed by names (stages, cameras), not a scalar of MetricNames()
  bool absent_when_zero = false;  // written only when non-zero; an expectation reads absence as 0
};

/// Every metric, concrete paths (placeholders expanded), in declaration order.
const std::vector<MetricSpec>& MetricRegistry();

/// The metric at a concrete path (a map's as "<path>.*"), or null. A pipeline's own measurement
/// type's NIS (`nis.<name>.<field>`, slam::MeasurementType) is found as the shipped types' are.
const MetricSpec* FindMetric(MetricScope scope, std::string_view path);

/// Whether `metric` is one of `names` (MetricNames() or EvaluationMetricNames()) or, where
/// `names` has the landmark types' NIS, a declared measurement type's NIS (`nis.<name>.mean`).
bool IsKnownMetric(const std::vector<std::string>& names, const std::string& metric);

/// Writes one JSON object's metrics through the registry: the value at prefix + name, rounded to
/// the declared step. An undeclared path or a unit that does not fit is a bug (aborts).
class MetricWriter {
 public:
  MetricWriter(nlohmann::ordered_json& root, MetricScope scope, std::string prefix = "");

  /// A writer for the object at prefix + name (e.g. Sub("map").Sub("lamp")).
  MetricWriter Sub(std::string_view name) const;

  void Set(std::string_view name, double value) const;
  void Set(std::string_view name, const std::optional<double>& value) const;  // null when empty
  void Count(std::string_view name, std::size_t count) const;  // skipped if absent_when_zero and 0
  /// numerator / denominator, null when the denominator is 0.
  void Fraction(std::string_view name, std::size_t numerator, std::size_t denominator) const;
  void Null(std::string_view name) const;

  /// A map metric: its object (present even when empty) and its entries.
  void Map(std::string_view name) const;
  void MapValue(std::string_view name, const std::string& key, double value) const;
  void MapCount(std::string_view name, const std::string& key, std::size_t count) const;

 private:
  const MetricSpec& Spec(const std::string& path) const;
  nlohmann::ordered_json& Slot(const std::string& path) const;

  nlohmann::ordered_json* root_;
  MetricScope scope_;
  std::string prefix_;
};

/// The docs section names, in order, and the markdown table of one.
std::vector<std::string> MetricsDocsSections();
std::string MetricsDocsTable(std::string_view section);

/// `markdown` with every generated block replaced by the registry's table:
///   <!-- BEGIN metrics-table SECTION -->  ...  <!-- END metrics-table SECTION -->
/// Throws std::runtime_error when a section has no block, a block names no section, or a
/// marker is unpaired.
std::string UpdateMetricsDocs(const std::string& markdown);

}  // namespace metrics
}  // namespace corridorsim
