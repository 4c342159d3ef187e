#include "harness/run/run_folder.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "common/error.h"
#include "common/installation.h"
#include "common/io/atomic_file.h"
#include "common/io/child_process.h"
#include "common/io/stable_json.h"
#include "common/io/yaml_reader.h"
#include "harness/run/provenance.h"
#include "harness/run/run.h"
#include "harness/run/run_io.h"
#include "harness/scenario/scenario.h"
#include "worlds/world_io.h"

namespace corridorsim {
std::string FormatFixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

namespace {

// Bytes of a failure's reason in the closing table's row.
constexpr std::size_t kTableReasonBytes = 160;

// A number from metrics.json for the closing table ("-" when absent).
std::string Cell(const nlohmann::ordered_json& m, const char* key, int decimals) {
  if (!m.contains(key) || !m[key].is_number()) return "-";
  return FormatFixed(m[key].get<double>(), decimals);
}

}  // namespace

ScoredRun ScoreRun(const MetricsInput& input, const std::vector<Expectation>& expectations) {
  ScoredRun scored;
  scored.metrics = ComputeMetrics(input);
  scored.results = CheckExpectations(scored.metrics, expectations);
  nlohmann::ordered_json& metrics = scored.metrics;
  metrics["run"] = {{"sim_seconds", metrics["run"]["sim_seconds"]}};
  scored.timing["pipelines"] = nlohmann::ordered_json::object();
  for (auto& [name, m] : metrics["pipelines"].items()) {
    if (m.contains("timing")) {
      scored.timing["pipelines"][name] = m["timing"];
      m.erase("timing");
    }
  }
  // An external pipeline's cost on both sides of the connection, failed ones' included.
  for (const PipelineRecord& record : input.pipelines) {
    if (!record.protocol_timing.is_null()) {
      scored.timing["pipelines"][record.name]["protocol"] = record.protocol_timing;
    }
  }
  nlohmann::ordered_json expectation_json = nlohmann::ordered_json::array();
  for (const ExpectationResult& r : scored.results) {
    scored.all_passed = scored.all_passed && r.passed;
    nlohmann::ordered_json j;
    j["text"] = r.expectation.text;
    j["measured"] = r.measured ? nlohmann::ordered_json(*r.measured) : nlohmann::ordered_json();
    j["passed"] = r.passed;
    expectation_json.push_back(std::move(j));
  }
  metrics["expectations"] = std::move(expectation_json);
  return scored;
}

void WriteRunFolder(const std::filesystem::path& out, const Scenario& scenario, std::uint64_t seed,
                    const worlds::World& world, const TruthRecorder& truth,
                    const PipelineRunner& pipelines, const nlohmann::ordered_json& metrics,
                    const std::string& events_json, const render::Backend* backend) {
  const std::string scenario_yaml = ResolvedScenarioYaml(scenario, seed);
  WriteFileAtomic(out / "scenario.yaml", scenario_yaml);
  WriteFileAtomic(
      out / "provenance.json",
      JsonFileText(ProvenanceJson(scenario.file, scenario_yaml, seed, backend, scenario.plugins,
                                  ExternalProgramsJson(scenario), scenario.settings)));
  WriteFileAtomic(out / "world.json", JsonFileText(worlds::GroundTruthJson(world)));
  WriteFileAtomic(out / "ground_truth.tum", truth.PlanarTum());
  for (const PipelineRecord& record : pipelines.records()) {
    std::ostringstream tum, cov;
    tum << "# " << record.name << ": estimated world_from_robot\n"
        << "# timestamp tx ty tz qx qy qz qw\n";
    cov << "# " << record.name << ": estimate with covariance (OpenVINS ov_eval)\n"
        << OvEvalHeader();
    for (const EstimateSample& e : record.estimates) {
      tum << sim::TumLine(e.stamp_ns, SE3::FromSE2(e.world_from_robot)) << "\n";
      cov << OvEvalLine(e.stamp_ns, e.world_from_robot, e.covariance) << "\n";
    }
    WriteFileAtomic(out / (record.name + ".tum"), tum.str());
    WriteFileAtomic(out / (record.name + "_cov.txt"), cov.str());
    WriteFileAtomic(out / (record.name + "_errors.csv"), ErrorSeriesCsv(truth.poses(), record));
    if (const std::string nis = NisSeriesCsv(record); !nis.empty()) {
      WriteFileAtomic(out / (record.name + "_nis.csv"), nis);
    }
    if (!record.landmarks.empty()) {
      WriteFileAtomic(out / (record.name + "_landmarks.json"),
                      JsonFileText(LandmarksJson(record.landmarks)));
    }
    if (!record.detections.empty()) {
      WriteFileAtomic(out / (record.name + "_detections.csv"), DetectionsCsv(record.detections));
    }
    if (!record.log.empty()) WriteFileAtomic(out / (record.name + ".log"), record.log);
  }
  WriteFileAtomic(out / "metrics.json", JsonFileText(metrics));
  WriteFileAtomic(out / "events.json", events_json);
}

void PrintClosingTable(const nlohmann::ordered_json& metrics,
                       const std::vector<ExpectationResult>& results,
                       const std::vector<const PipelineRecord*>& failed) {
  std::printf("\n%-22s %10s %12s %12s %10s %12s\n", "pipeline", "ATE rmse m", "ATE aligned",
              "final err m", "NEES mean", "NEES in band");
  if (metrics.contains("pipelines")) {
    for (const auto& [name, m] : metrics["pipelines"].items()) {
      // Not captured by the lambda: clang 14 (the sanitized tree) refuses a captured binding.
      const std::string& pipeline = name;
      const auto record = std::find_if(failed.begin(), failed.end(), [&](const PipelineRecord* r) {
        return r->name == pipeline && r->failure;
      });
      if (record != failed.end()) {
        // No metric of it could be compared: the row says so, with when and why (in full on
        // stderr below the table).
        const PipelineFailure& f = *(*record)->failure;
        std::printf("%-22s failed at t = %.3f s (%s): %s\n", name.c_str(), ToSeconds(f.stamp_ns),
                    f.call.c_str(), InputExcerpt(f.what, kTableReasonBytes).c_str());
        continue;
      }
      std::printf("%-22s %10s %12s %12s %10s %12s\n", name.c_str(),
                  Cell(m, "ate_rmse_m", 3).c_str(), Cell(m, "ate_aligned_rmse_m", 3).c_str(),
                  Cell(m, "final_position_error_m", 3).c_str(), Cell(m, "nees_mean", 2).c_str(),
                  Cell(m, "nees_in_band_fraction", 3).c_str());
    }
  }
  if (results.empty()) return;
  std::printf("\nexpectations:\n");
  for (const ExpectationResult& r : results) {
    const std::string measured = r.measured ? FormatFixed(*r.measured, 4) : "missing";
    std::printf("  %s  %-45s measured %s\n", r.passed ? "PASS" : "FAIL", r.expectation.text.c_str(),
                measured.c_str());
  }
}

std::string PlotPython() {
  if (const char* python = std::getenv("CORRIDORSIM_PYTHON"); python && *python) return python;
  std::error_code error;
  if (std::filesystem::is_regular_file("/usr/bin/python3", error)) return "/usr/bin/python3";
  return "python3";
}

std::optional<std::string> RunPlotScript(const std::string& script,
                                         const std::vector<std::string>& args) {
  const std::filesystem::path path = DataDir() / "scripts" / script;
  const std::string python = PlotPython();
  std::vector<std::string> argv = {python, path.string()};
  argv.insert(argv.end(), args.begin(), args.end());
  // The installed Python package (corridorsim.files: the run folder's readers) on its path.
  ChildOptions options;
  if (const std::string python_path = PythonPathWithPackage(); !python_path.empty()) {
    options.environment.emplace_back("PYTHONPATH", python_path);
  }
  ChildProcess child(argv, options);
  const ChildStatus status = child.Wait();
  if (status.succeeded()) return std::nullopt;
  std::string command = python + " '" + path.string() + "'";
  for (const std::string& a : args) command += " '" + a + "'";
  return command + " " + DescribeChildStatus(status);
}

std::optional<std::string> MakePlots(const std::filesystem::path& out) {
  return RunPlotScript("plot_run.py", {out.string()});
}

std::optional<std::string> MakeViewer(const std::filesystem::path& out) {
  return RunPlotScript("make_viewer.py", {out.string()});
}

std::unique_ptr<StagedDirectory> StageOutputFolder(const std::filesystem::path& dir,
                                                   const std::string& option, bool force,
                                                   const std::vector<JobInput>& inputs) {
  const SourceLocation command_line{"command line", 0, 0};
  // The current folder first: it holds the inputs too, and this is what to change.
  std::error_code cwd_error;
  const std::filesystem::path cwd = std::filesystem::current_path(cwd_error);
  if (!cwd_error && PathWithin(cwd, dir)) {
    throw InputError(command_line, option,
                     "output folder '" + dir.string() +
                         "' is the current folder or contains it; choose a folder below it");
  }
  RefuseOutputOverInputs(dir, option, inputs);
  try {
    return std::make_unique<StagedDirectory>(dir, force);
  } catch (const FolderNotEmptyError&) {
    throw InputError(command_line, option,
                     "'" + dir.string() +
                         "' is not empty (a previous run?): pass --force to replace it whole, "
                         "or choose another folder");
  } catch (const std::exception& e) {
    throw InputError(command_line, option, e.what());
  }
}

int CommitResultsThenExtras(StagedDirectory& folder,
                            const std::function<void(const std::filesystem::path&)>& write_results,
                            const std::vector<RunExtra>& extras) {
  write_results(folder.path());
  folder.Commit();
  int failed = 0;
  for (const RunExtra& extra : extras) {
    try {
      extra.write();
    } catch (const std::exception& e) {
      ++failed;
      std::fflush(stdout);
      std::fprintf(stderr, "corridorsim: error: %s: %s; the results are written in %s\n",
                   extra.name.c_str(), e.what(), folder.path().string().c_str());
    }
  }
  return failed;
}

int RunExitCode(bool all_expectations_passed, int extras_failed, bool pipeline_failed) {
  if (pipeline_failed) return kExitPipelineFailed;
  if (!all_expectations_passed) return kExitExpectationsFailed;
  return extras_failed > 0 ? kExitExtraFailed : 0;
}

}  // namespace corridorsim
