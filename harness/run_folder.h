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
#include "harness/scenario.h"
#include "harness/truth_recorder.h"
#include "render/backend.h"
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

/// Writes scenario.yaml (the echo of `scenario` as loaded, with `seed`), provenance.json,
/// world.json, ground_truth.tum, each pipeline's .tum, _cov.txt, _errors.csv and maps,
/// metrics.json and events.json into `out` (atomically, file by file). `backend` is the GL
/// backend the run rendered with, or null.
void WriteRunFolder(const std::filesystem::path& out, const Scenario& scenario, std::uint64_t seed,
                    const worlds::World& world, const TruthRecorder& truth,
                    const PipelineRunner& pipelines, const nlohmann::ordered_json& metrics,
                    const std::string& events_json, const render::Backend* backend);

/// `v` with `decimals` digits after the point ("%.*f"), for tables, live lines and CSV.
std::string FormatFixed(double v, int decimals);

/// The closing table: each pipeline's main metrics, then every expectation with its value.
void PrintClosingTable(const nlohmann::ordered_json& metrics,
                       const std::vector<ExpectationResult>& results);

/// Runs scripts/plot_run.py on the run folder. Returns an error message, or nothing.
std::optional<std::string> MakePlots(const std::filesystem::path& out);

}  // namespace corridorsim
