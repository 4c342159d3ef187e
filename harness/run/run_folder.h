#pragma once
// The finishing step of `corridorsim run`: the run folder's files (README.md lists them) and
// the closing report. Every file but timing.json is byte-identical for one scenario and seed.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/io/atomic_file.h"
#include "harness/metrics/metrics.h"
#include "harness/run/job_inputs.h"
#include "harness/run/pipeline_runner.h"
#include "harness/run/truth_recorder.h"
#include "harness/scenario/scenario.h"
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
/// world.json, ground_truth.tum, each pipeline's .tum, _cov.txt, _errors.csv, metrics.json and
/// events.json into `out` (atomically, file by file). Maps are an extra (RunExtra), written after
/// the folder is committed. `backend` is the GL backend the run rendered with, or null.
void WriteRunFolder(const std::filesystem::path& out, const Scenario& scenario, std::uint64_t seed,
                    const worlds::World& world, const TruthRecorder& truth,
                    const PipelineRunner& pipelines, const nlohmann::ordered_json& metrics,
                    const std::string& events_json, const render::Backend* backend);

/// `v` with `decimals` digits after the point ("%.*f"), for tables, live lines and CSV.
std::string FormatFixed(double v, int decimals);

/// The closing table: each pipeline's main metrics (a failed one: `failed`, when and why), then
/// every expectation with its value.
void PrintClosingTable(const nlohmann::ordered_json& metrics,
                       const std::vector<ExpectationResult>& results,
                       const std::vector<const PipelineRecord*>& failed = {});

/// The Python that runs the plot scripts: $CORRIDORSIM_PYTHON when set, else Debian's
/// /usr/bin/python3 when it exists (the one python3-matplotlib serves, whatever python3 comes
/// first on PATH), else `python3` from PATH.
std::string PlotPython();

/// Runs `PlotPython() <data>/scripts/plot_run.py <out>` (no shell: the folder's name is one
/// argument whatever it holds). Returns an error message, or nothing.
std::optional<std::string> MakePlots(const std::filesystem::path& out);

/// Runs `PlotPython() <data>/scripts/make_viewer.py <out>`: <out>/viewer.html (docs/viewer.md).
/// Returns an error message, or nothing.
std::optional<std::string> MakeViewer(const std::filesystem::path& out);

/// Runs `PlotPython() <data>/scripts/<script> <args>...` (no shell), with the installed Python
/// package on its PYTHONPATH (PythonPathWithPackage). Returns an error message, or
/// nothing.
std::optional<std::string> RunPlotScript(const std::string& script,
                                         const std::vector<std::string>& args);

/// A job's output folder (`option`: "--out", "--export"), staged (StagedDirectory): a folder that
/// is, contains or lies inside one of the job's `inputs` (RefuseOutputOverInputs), a path that
/// names no usable folder, and a folder that holds files without `force`, are InputError at
/// `command line: <option>`, before anything runs.
std::unique_ptr<StagedDirectory> StageOutputFolder(const std::filesystem::path& dir,
                                                   const std::string& option, bool force,
                                                   const std::vector<JobInput>& inputs);

/// Something a run writes after its results are committed: maps/, the --export dataset, plots/.
/// `write` throws (any std::exception) on failure.
struct RunExtra {
  std::string name;  // in the message: "maps/", "plots/", "--export dataset"
  std::function<void()> write;
};

/// Results first, extras after: `write_results` writes into the staging folder, the folder is
/// committed (a failure there throws: the previous folder is left as it was), then every extra
/// runs in order; an extra that fails is reported on stderr (`corridorsim: error: <name>: ...;
/// the results are written`) and the next still runs. Returns how many extras failed.
int CommitResultsThenExtras(StagedDirectory& folder,
                            const std::function<void(const std::filesystem::path&)>& write_results,
                            const std::vector<RunExtra>& extras);

/// A finished run's exit code: kExitPipelineFailed (5) when a pipeline failed, else
/// kExitExpectationsFailed (3) when an expectation failed, else kExitExtraFailed (4) when an extra
/// failed, else 0.
int RunExitCode(bool all_expectations_passed, int extras_failed, bool pipeline_failed = false);

}  // namespace corridorsim
