#pragma once
// The scenario `expectations` that assert on metrics.json, e.g.
// "p1_vp_doorplate.ate_rmse_m < 0.15" (docs/metrics.md, Expectations).

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace corridorsim {

struct Expectation {
  enum class Op { kLess, kLessEqual, kGreater, kGreaterEqual };
  std::string pipeline;  // the pipeline's name
  std::string metric;    // dotted path under the pipeline's object, one of MetricNames()
  Op op = Op::kLess;
  double value = 0.0;
  std::string text;  // as written
};

/// Parses "<pipeline>.<metric> <op> <number>", op one of < <= > >=, the metric one of `names`
/// (a scenario's: MetricNames(); `corridorsim evaluate`'s: EvaluationMetricNames()). Returns the
/// error message, or nothing on success (then *out is set).
std::optional<std::string> ParseExpectation(const std::string& text, Expectation* out);
std::optional<std::string> ParseExpectation(const std::string& text, Expectation* out,
                                            const std::vector<std::string>& names);

struct ExpectationResult {
  Expectation expectation;
  std::optional<double> measured;  // empty: the metric is missing or null (the check fails)
  bool passed = false;
};

/// Each expectation against `metrics` (ComputeMetrics' object; its pipelines are the objects
/// under `group`: evaluation.json's are under "estimates"). A missing or null metric fails,
/// except a counter the registry writes only when non-zero: in an existing pipeline its absence
/// reads as 0.
std::vector<ExpectationResult> CheckExpectations(const nlohmann::ordered_json& metrics,
                                                 const std::vector<Expectation>& expectations,
                                                 const std::string& group = "pipelines");

}  // namespace corridorsim
