#include "harness/run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <set>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/serial_worker.h"
#include "harness/calibration.h"
#include "harness/export.h"
#include "harness/frame_io.h"
#include "harness/metrics.h"
#include "harness/progress.h"
#include "harness/run_io.h"
#include "harness/scenario.h"
#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/scene.h"
#include "sim/simulation.h"
#include "slam/pipeline.h"
#include "worlds/world_io.h"

namespace corridorsim {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// One pipeline with everything the metrics need, recorded as the run goes.
struct PipelineRun {
  std::unique_ptr<slam::Pipeline> pipeline;
  std::set<std::string> cameras;
  PipelineRecord record;
  double seconds = 0.0;  // wall time inside the pipeline
};

// The truth pose at `stamp` from the 100 Hz record (the last one not after it).
const TruthPose* TruthAt(const std::vector<TruthPose>& truth, TimeNs stamp) {
  auto it = std::upper_bound(truth.begin(), truth.end(), stamp,
                             [](TimeNs t, const TruthPose& p) { return t < p.stamp_ns; });
  return it == truth.begin() ? nullptr : &*(it - 1);
}

std::string Fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
  return buf;
}

// A number from metrics.json for the closing table ("-" when absent).
std::string Cell(const nlohmann::ordered_json& m, const char* key, int decimals) {
  if (!m.contains(key) || !m[key].is_number()) return "-";
  return Fixed(m[key].get<double>(), decimals);
}

void PrintClosingTable(const nlohmann::ordered_json& metrics,
                       const std::vector<ExpectationResult>& results) {
  std::printf("\n%-22s %10s %12s %12s %10s %12s\n", "pipeline", "ATE rmse m", "ATE aligned",
              "final err m", "NEES mean", "NEES in band");
  if (metrics.contains("pipelines")) {
    for (const auto& [name, m] : metrics["pipelines"].items()) {
      std::printf("%-22s %10s %12s %12s %10s %12s\n", name.c_str(),
                  Cell(m, "ate_rmse_m", 3).c_str(), Cell(m, "ate_aligned_rmse_m", 3).c_str(),
                  Cell(m, "final_position_error_m", 3).c_str(), Cell(m, "nees_mean", 2).c_str(),
                  Cell(m, "nees_in_band_fraction", 3).c_str());
    }
  }
  if (results.empty()) return;
  std::printf("\nexpectations:\n");
  for (const ExpectationResult& r : results) {
    const std::string measured = r.measured ? Fixed(*r.measured, 4) : "missing";
    std::printf("  %s  %-45s measured %s\n", r.passed ? "PASS" : "FAIL", r.expectation.text.c_str(),
                measured.c_str());
  }
}

// Runs scripts/plot_run.py on the run folder. Returns an error message, or nothing.
std::optional<std::string> MakePlots(const std::filesystem::path& out) {
  const std::filesystem::path script =
      std::filesystem::path(CORRIDORSIM_SCRIPTS_DIR) / "plot_run.py";
  const std::string command = "python3 '" + script.string() + "' '" + out.string() + "'";
  const int rc = std::system(command.c_str());
  if (rc != 0) return "plots failed (" + command + " exited " + std::to_string(rc) + ")";
  return std::nullopt;
}

}  // namespace

int RunScenario(const RunRequest& request) {
  const Clock::time_point run_start = Clock::now();
  const Scenario scenario = LoadScenario(request.scenario_file);
  const std::vector<Expectation> expectations = ScenarioExpectations(scenario);
  const render::BackendKind backend_kind = ChooseBackend(scenario.rig.backend);
  const std::filesystem::path& out = request.out_dir;
  // Output folders are checked before anything runs: a run never ends unable to write.
  if (!request.check_only) {
    EnsureOutputDirectory(out, "--out");
    if (request.plots) EnsureOutputDirectory(out / "plots", "--out");
  }
  if (request.export_dir && !request.check_only) {
    EnsureOutputDirectory(*request.export_dir, "--export");
  }
  const std::uint64_t seed = request.seed.value_or(scenario.seed);
  const worlds::World world = GenerateWorld(scenario, seed);
  sim::RobotPath path = BuildScenarioRobotPath(scenario, world);
  const SE2 start = path.world_from_start;

  // Pipelines, all on the same stream.
  const slam::Calibration calibration = CalibrationOf(scenario);
  std::vector<PipelineRun> runs;
  std::set<std::string> cameras_needed;
  for (const Scenario::PipelineEntry& entry : scenario.pipelines) {
    if (!entry.enabled) continue;
    PipelineRun run;
    run.pipeline = entry.config->Create(calibration);
    run.record.name = entry.name;
    run.record.cameras_used = run.pipeline->cameras_used();
    for (const std::string& id : run.pipeline->cameras_used()) {
      if (!calibration.Find(id)) {
        throw LocateProblem(scenario, "pipelines",
                            OptionsProblem{entry.name, "reads the camera '" + id +
                                                           "', which is not enabled in sensors:"});
      }
      run.cameras.insert(id);
      cameras_needed.insert(id);
    }
    run.pipeline->Initialize(0, start);
    runs.push_back(std::move(run));
  }
  // Render only what somebody reads: the pipelines' cameras, or every enabled one for --export.
  render::RigOptions rig_options = scenario.rig;
  for (render::CameraOptions& c : rig_options.cameras) {
    c.enabled = c.enabled && (request.export_dir || cameras_needed.count(c.id));
  }
  const bool render_any = std::any_of(rig_options.cameras.begin(), rig_options.cameras.end(),
                                      [](const render::CameraOptions& c) { return c.enabled; });
  std::optional<render::Scene> scene;
  std::unique_ptr<render::Backend> backend;
  std::unique_ptr<render::Rig> rig;
  if (auto problem = render::CheckCameraPlacement(world, scenario.rig, SE3::FromSE2(start))) {
    throw LocateProblem(scenario, "sensors", *problem);
  }
  if (render_any && !request.check_only) {
    scene = render::BuildScene(world, rig_options.scene);
    backend = render::CreateBackend(backend_kind);
    backend->Upload(*scene);
    rig = std::make_unique<render::Rig>(rig_options, *scene, *backend);
  }
  if (request.check_only) {
    std::printf("ok: %s (world %zu meshes, path %s %.1f m, %zu pipeline(s), %zu expectation(s))\n",
                request.scenario_file.c_str(), world.meshes.size(),
                sim::PathKindName(scenario.robot_path.kind).c_str(), path.length_m(), runs.size(),
                expectations.size());
    return 0;
  }
  std::optional<DatasetExporter> exporter;
  if (request.export_dir) {
    try {
      exporter.emplace(*request.export_dir, rig_options, scenario.robot.wheelbase_m);
    } catch (const std::runtime_error& e) {
      throw InputError(SourceLocation{"command line", 0, 0}, "--export", e.what());
    }
  }
  // The export encodes and writes on a worker thread, in submission order, while the next frames
  // render (PNG encoding cost as much as rendering); a few frames may wait, no more.
  std::optional<SerialWorker> export_worker;
  if (exporter) export_worker.emplace(4);

  sim::SimulationOptions options;
  options.robot = scenario.robot;
  options.robot_path = scenario.robot_path;
  options.seed = seed;
  options.max_duration_ns = FromSeconds(scenario.duration_s);
  sim::Simulation simulation(world, options, std::move(path), rig.get(), &rig_options);
  std::vector<std::string> rendered_ids;
  if (rig) {
    for (const render::CameraRenderer& c : rig->cameras()) rendered_ids.push_back(c.options().id);
  }

  std::printf(
      "run: %s, seed %llu, %zu pipeline(s)%s, path %s (%.1f m)%s\n",
      scenario.name.empty() ? request.scenario_file.c_str() : scenario.name.c_str(),
      static_cast<unsigned long long>(seed), runs.size(),
      [&] {
        std::string names;
        for (const PipelineRun& r : runs) names += (names.empty() ? ": " : ", ") + r.record.name;
        return names;
      }()
          .c_str(),
      sim::PathKindName(scenario.robot_path.kind).c_str(), simulation.path().length_m(),
      render_any ? ", rendering cameras" : "");

  MetricsInput input;
  input.world = &world;
  nlohmann::ordered_json events = nlohmann::ordered_json::array();
  const TimeNs truth_period = PeriodFromRateHz(kTruthFileRateHz);
  input.truth.push_back({0, simulation.truth().world_from_robot_2d});
  if (exporter) {
    const SE3 pose = simulation.truth().state.world_from_robot;
    export_worker->Submit([&exporter, pose] { exporter->AddTruth(0, pose); }, 0);
  }
  double step_seconds = 0.0;
  double export_seconds = 0.0;       // the export worker's busy time (overlaps the loop)
  double export_wait_seconds = 0.0;  // the loop waiting on it (queue full, final drain)
  Progress progress("run");
  const Clock::time_point loop_start = Clock::now();
  while (!simulation.finished()) {
    const Clock::time_point t_step = Clock::now();
    const sim::StepOutput& step = simulation.Step();
    step_seconds += Since(t_step);
    const TimeNs now = step.truth.stamp_ns;
    if (now % truth_period == 0) {
      input.truth.push_back({now, step.truth.world_from_robot_2d});
      if (exporter) {
        const SE3 pose = step.truth.state.world_from_robot;
        export_worker->Submit([&exporter, now, pose] { exporter->AddTruth(now, pose); }, 0);
      }
    }
    for (const WheelOdometry& odometry : step.odometry) {
      if (exporter) {
        export_worker->Submit([&exporter, odometry] { exporter->AddOdometry(odometry); }, 0);
      }
      for (PipelineRun& run : runs) {
        const Clock::time_point t0 = Clock::now();
        run.pipeline->OnOdometry(odometry);
        const slam::PoseEstimate e = run.pipeline->Estimate();
        run.seconds += Since(t0);
        run.record.estimates.push_back({odometry.stamp_ns, e.world_from_robot, e.covariance});
      }
    }
    for (const sim::CameraMessage& message : step.frames) {
      const std::string& id = rendered_ids[message.camera];
      if (exporter) {
        const Clock::time_point t0 = Clock::now();
        export_worker->Submit(
            [&exporter, message, id] { exporter->AddFrame(message, id); });  // copies the frame
        export_wait_seconds += Since(t0);
      }
      if (!cameras_needed.count(id)) continue;
      input.frames.push_back({message.stamp_ns, message.truth});
      slam::CameraInput camera_input;
      camera_input.image = StampedImage{message.stamp_ns, id, message.frame.rgb};
      if (!message.frame.noisy_depth_m.data.empty()) {
        camera_input.depth = StampedDepth{message.stamp_ns, id, message.frame.noisy_depth_m};
      }
      for (PipelineRun& run : runs) {
        if (!run.cameras.count(id)) continue;
        const Clock::time_point t0 = Clock::now();
        run.pipeline->OnCamera(camera_input);
        run.seconds += Since(t0);
        for (slam::Detection& d : run.pipeline->TakeDetections()) {
          run.record.detections.push_back(std::move(d));
        }
      }
    }
    for (const sim::Event& e : step.events) events.push_back(EventJson(e));
    // The live line (every 0.1 s of simulated time, or at the end): each pipeline's current
    // position error against the truth.
    if (now % (10 * truth_period) != 0 && !simulation.finished()) continue;
    std::string errors;
    for (const PipelineRun& run : runs) {
      if (run.record.estimates.empty()) continue;
      const EstimateSample& e = run.record.estimates.back();
      if (const TruthPose* t = TruthAt(input.truth, e.stamp_ns)) {
        errors +=
            run.record.name + " " +
            Fixed((e.world_from_robot.translation() - t->world_from_robot.translation()).norm(),
                  3) +
            " m  ";
      }
    }
    progress.Update(now, simulation.progress(), errors);
  }
  progress.Finish();
  if (simulation.now_ns() % truth_period != 0) {
    input.truth.push_back({simulation.now_ns(), simulation.truth().world_from_robot_2d});
  }
  double pipeline_seconds = 0.0;
  for (PipelineRun& run : runs) {
    run.record.landmarks = run.pipeline->Landmarks();
    for (slam::Innovation& i : run.pipeline->TakeInnovations()) {
      run.record.innovations.push_back(i);
    }
    run.record.stage_seconds = run.pipeline->stage_seconds();
    run.record.health = run.pipeline->health();
    pipeline_seconds += run.seconds;
  }
  for (PipelineRun& run : runs) input.pipelines.push_back(run.record);

  // Metrics (deterministic) and timing (wall clock) go to separate files, so that metrics.json
  // is byte-identical between runs of one scenario and seed. The run's own stage split is
  // written below (ComputeMetrics gets no wall times, so its `run` holds sim_seconds only); each
  // pipeline's `timing` section moves to timing.json after the expectations saw it.
  const Clock::time_point t_metrics = Clock::now();
  const double render_seconds = simulation.render_seconds();
  input.timing.sim_seconds = ToSeconds(simulation.now_ns());
  nlohmann::ordered_json metrics = ComputeMetrics(input);
  const std::vector<ExpectationResult> results = CheckExpectations(metrics, expectations);
  metrics["run"] = {{"sim_seconds", metrics["run"]["sim_seconds"]}};
  nlohmann::ordered_json timing;
  timing["pipelines"] = nlohmann::ordered_json::object();
  for (auto& [name, m] : metrics["pipelines"].items()) {
    if (m.contains("timing")) {
      timing["pipelines"][name] = m["timing"];
      m.erase("timing");
    }
  }
  bool all_passed = true;
  nlohmann::ordered_json expectation_json = nlohmann::ordered_json::array();
  for (const ExpectationResult& r : results) {
    all_passed = all_passed && r.passed;
    nlohmann::ordered_json j;
    j["text"] = r.expectation.text;
    j["measured"] = r.measured ? nlohmann::ordered_json(*r.measured) : nlohmann::ordered_json();
    j["passed"] = r.passed;
    expectation_json.push_back(std::move(j));
  }
  metrics["expectations"] = std::move(expectation_json);
  const double metrics_seconds = Since(t_metrics);

  // The run folder.
  const Clock::time_point t_write = Clock::now();
  WriteFileAtomic(out / "scenario.yaml", ResolvedScenarioYaml(request.scenario_file, seed));
  WriteFileAtomic(out / "world.json", worlds::GroundTruthJson(world).dump(2) + "\n");
  {
    std::ostringstream tum;
    tum << "# ground truth: world_from_robot at 100 Hz\n# timestamp tx ty tz qx qy qz qw\n";
    for (const TruthPose& t : input.truth) {
      tum << sim::TumLine(t.stamp_ns, SE3::FromSE2(t.world_from_robot)) << "\n";
    }
    WriteFileAtomic(out / "ground_truth.tum", tum.str());
  }
  for (const PipelineRun& run : runs) {
    std::ostringstream tum, cov;
    tum << "# " << run.record.name << ": estimated world_from_robot\n"
        << "# timestamp tx ty tz qx qy qz qw\n";
    cov << "# " << run.record.name << ": estimate with covariance (OpenVINS ov_eval)\n"
        << OvEvalHeader();
    for (const EstimateSample& e : run.record.estimates) {
      tum << sim::TumLine(e.stamp_ns, SE3::FromSE2(e.world_from_robot)) << "\n";
      cov << OvEvalLine(e.stamp_ns, e.world_from_robot, e.covariance) << "\n";
    }
    WriteFileAtomic(out / (run.record.name + ".tum"), tum.str());
    WriteFileAtomic(out / (run.record.name + "_cov.txt"), cov.str());
    WriteFileAtomic(out / (run.record.name + "_errors.csv"),
                    ErrorSeriesCsv(input.truth, run.record));
    const std::filesystem::path maps = out / "maps";
    if (!run.pipeline->WriteMaps(maps / run.record.name).empty()) {
      std::printf("  %s wrote maps to %s\n", run.record.name.c_str(),
                  (maps / run.record.name).string().c_str());
    }
  }
  WriteFileAtomic(out / "metrics.json", metrics.dump(2) + "\n");
  nlohmann::ordered_json events_json;
  events_json["seed"] = seed;
  events_json["duration_s"] = ToSeconds(simulation.now_ns());
  events_json["events"] = std::move(events);
  WriteFileAtomic(out / "events.json", events_json.dump(2) + "\n");
  const double write_seconds = Since(t_write);
  if (exporter) {
    const Clock::time_point t0 = Clock::now();
    export_worker->Submit([&exporter] { exporter->Finish(); });
    export_worker->Drain();
    export_wait_seconds += Since(t0);
    export_seconds = export_worker->busy_seconds();
  }

  std::optional<std::string> plot_error;
  const Clock::time_point t_plots = Clock::now();
  if (request.plots) plot_error = MakePlots(out);
  const double plot_seconds = Since(t_plots);

  // Wall-clock cost by stage (physics = the simulation step minus its rendering), the whole run.
  const double total = Since(run_start);
  const double sim_s = ToSeconds(simulation.now_ns());
  timing["sim_seconds"] = sim_s;
  timing["wall_seconds"] = total;
  timing["real_time_factor"] = total > 0 ? sim_s / total : 0.0;
  timing["stages_seconds"] = {
      {"setup", std::chrono::duration<double>(loop_start - run_start).count()},
      {"physics", step_seconds - render_seconds},
      {"rendering", render_seconds},
      {"pipelines", pipeline_seconds},
      {"metrics", metrics_seconds},
      {"writing", write_seconds},
      {"export", export_seconds},
      {"export_wait", export_wait_seconds},
      {"plots", plot_seconds}};
  WriteFileAtomic(out / "timing.json", timing.dump(2) + "\n");

  PrintClosingTable(metrics, results);
  std::printf(
      "\nrun: %.1f s simulated in %.1f s (real-time factor %.1fx): physics %.1f s, "
      "rendering %.1f s, pipelines %.2f s, metrics %.2f s, writing %.2f s, export %.1f s, plots "
      "%.1f s\n",
      sim_s, total, timing["real_time_factor"].get<double>(), step_seconds - render_seconds,
      render_seconds, pipeline_seconds, metrics_seconds, write_seconds, export_seconds,
      plot_seconds);
  std::printf(
      "wrote %s/{scenario.yaml, world.json, ground_truth.tum, <pipeline>.tum, "
      "<pipeline>_cov.txt, <pipeline>_errors.csv, metrics.json, timing.json, events.json%s}%s\n",
      out.string().c_str(), request.plots ? ", plots/" : "",
      request.export_dir ? (" and the dataset in " + request.export_dir->string()).c_str() : "");
  if (!simulation.path_done()) {
    std::printf("warning: the path was not finished (see events.json)\n");
  }
  if (plot_error) throw std::runtime_error(*plot_error);
  return all_passed ? 0 : kExitExpectationsFailed;
}

}  // namespace corridorsim
