#pragma once
// The finishing step of `corridorsim run`: the run folder's files (README.md lists them) and
// the closing report. Every file but timing.json is byte-identical for one scenario and seed.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/metrics.h"
#include "harness/pipeline_runner.h"
#include "harness/truth_recorder.h"
#include "worlds/world.h"

namespace corridorsim {

/// metrics.json (ComputeMetrics with the expectations' results) and timing.json (each
/// pipeline's `timing` section moves there, so metrics.json holds nothing wall-clock).
struct ScoredRun {
  nlohmann::ordered_json metrics;
  nlohmann::ordered_json timing;
  std::vector<ExpectationResult> results;
  bool all_passed = true;
};
ScoredRun ScoreRun(const MetricsInput& input, const std::vector<Expectation>& expectations);

/// Writes scenario.yaml, world.json, ground_truth.tum, each pipeline's .tum, _cov.txt,
/// _errors.csv and maps, metrics.json and events.json into `out` (atomically, file by file).
void WriteRunFolder(const std::filesystem::path& out, const std::string& scenario_file,
                    std::uint64_t seed, const worlds::World& world, const TruthRecorder& truth,
                    const PipelineRunner& pipelines, const nlohmann::ordered_json& metrics,
                    const std::string& events_json);

/// `v` with `decimals` digits after the point ("%.*f"), for tables, live lines and CSV.
std::string FormatFixed(double v, int decimals);

/// The closing table: each pipeline's main metrics, then every expectation with its value.
void PrintClosingTable(const nlohmann::ordered_json& metrics,
                       const std::vector<ExpectationResult>& results);

/// Runs scripts/plot_run.py on the run folder. Returns an error message, or nothing.
std::optional<std::string> MakePlots(const std::filesystem::path& out);

}  // namespace corridorsim
