#include "harness/run.h"

#include <chrono>
#include <cstdio>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "common/io/atomic_file.h"
#include "harness/calibration.h"
#include "harness/export_consumer.h"
#include "harness/pipeline_runner.h"
#include "harness/progress.h"
#include "harness/run_folder.h"
#include "harness/scenario.h"
#include "harness/sensor_bus.h"
#include "harness/simulation_setup.h"
#include "harness/stopwatch.h"
#include "harness/truth_recorder.h"

namespace corridorsim {
// Build, loop, finish (docs/architecture.md, "How a run is made").
int RunScenario(const RunRequest& request) {
  const WallClock::time_point run_start = WallClock::now();
  const Scenario scenario = LoadScenario(request.scenario_file);
  const std::vector<Expectation> expectations = ScenarioExpectations(scenario);
  if (!request.export_dir) RequireScoredPipeline(scenario);  // else a run would score nothing
  const std::filesystem::path& out = request.out_dir;
  // Output folders are checked before anything runs: a run never ends unable to write.
  if (!request.check_only) {
    EnsureOutputDirectory(out, "--out");
    if (request.plots) EnsureOutputDirectory(out / "plots", "--out");
    if (request.export_dir) EnsureOutputDirectory(*request.export_dir, "--export");
  }

  // Build: the pipelines (all on the same stream), then the world, path and cameras they need.
  SimulationSetup setup(scenario, request.seed.value_or(scenario.seed),
                        /*check_camera_placement=*/true);
  PipelineRunner pipelines(scenario, CalibrationOf(scenario));
  pipelines.Initialize(0, setup.robot_path().world_from_start);
  if (request.check_only) {
    std::printf("ok: %s (world %zu meshes, path %s %.1f m, %zu pipeline(s), %zu expectation(s))\n",
                request.scenario_file.c_str(), setup.world().meshes.size(),
                sim::PathKindName(scenario.robot_path.kind).c_str(), setup.robot_path().length_m(),
                pipelines.size(), expectations.size());
    return 0;
  }
  // Render only what somebody reads: the pipelines' cameras, or every enabled one for --export.
  std::set<std::string> render_cameras = pipelines.cameras_used();
  if (request.export_dir) {
    for (const render::CameraOptions& c : scenario.rig.cameras) render_cameras.insert(c.id);
  }
  setup.Start(render_cameras);
  sim::Simulation& simulation = setup.simulation();
  std::optional<ExportConsumer> exporter;
  if (request.export_dir) {
    exporter.emplace(*request.export_dir, setup.rig_options(), scenario.robot.wheelbase_m);
  }
  std::printf("run: %s, seed %llu, %zu pipeline(s)%s, path %s (%.1f m)%s\n",
              scenario.name.empty() ? request.scenario_file.c_str() : scenario.name.c_str(),
              static_cast<unsigned long long>(setup.seed()), pipelines.size(),
              pipelines.size() ? (": " + pipelines.Names()).c_str() : "",
              sim::PathKindName(scenario.robot_path.kind).c_str(), simulation.path().length_m(),
              setup.camera_ids().empty() ? "" : ", rendering cameras");

  // Loop: the simulation publishes, the consumers listen.
  TruthRecorder truth(pipelines.cameras_used());
  EventLog events;
  ProgressLine progress("run", simulation, [&] { return pipelines.ErrorsLine(truth); });
  SensorBus bus(setup.camera_ids());
  bus.Subscribe(&truth);
  if (exporter) bus.Subscribe(&*exporter);
  bus.Subscribe(&pipelines);
  bus.Subscribe(&events);
  bus.Subscribe(&progress);
  const WallClock::time_point loop_start = WallClock::now();
  bus.Run(simulation);

  // Finish: pipelines, then metrics (deterministic) and timing (wall clock) in separate files.
  pipelines.Finish();
  const WallClock::time_point t_metrics = WallClock::now();
  MetricsInput input;
  input.world = &setup.world();
  input.truth = truth.poses();
  input.frames = truth.frames();
  input.pipelines = pipelines.records();
  input.timing.sim_seconds = ToSeconds(simulation.now_ns());
  ScoredRun scored = ScoreRun(input, expectations);
  const double metrics_seconds = SecondsSince(t_metrics);

  const WallClock::time_point t_write = WallClock::now();
  WriteRunFolder(out, scenario, setup.seed(), setup.world(), truth, pipelines, scored.metrics,
                 events.Json(setup.seed(), simulation.now_ns()), setup.backend());
  const double write_seconds = SecondsSince(t_write);
  double export_seconds = 0.0, export_wait_seconds = 0.0;
  if (exporter) {
    exporter->Finish();
    export_seconds = exporter->busy_seconds();
    export_wait_seconds = exporter->wait_seconds();
  }
  std::optional<std::string> plot_error;
  const WallClock::time_point t_plots = WallClock::now();
  if (request.plots) plot_error = MakePlots(out);
  const double plot_seconds = SecondsSince(t_plots);

  // Wall-clock cost by stage (physics = the simulation step minus its rendering), the whole run.
  const double total = SecondsSince(run_start);
  const double sim_s = ToSeconds(simulation.now_ns());
  const double render_seconds = simulation.render_seconds();
  const double physics_seconds = bus.step_seconds() - render_seconds;
  nlohmann::ordered_json& timing = scored.timing;
  timing["sim_seconds"] = sim_s;
  timing["wall_seconds"] = total;
  timing["real_time_factor"] = total > 0 ? sim_s / total : 0.0;
  timing["stages_seconds"] = {
      {"setup", std::chrono::duration<double>(loop_start - run_start).count()},
      {"physics", physics_seconds},
      {"rendering", render_seconds},
      {"pipelines", pipelines.seconds()},
      {"metrics", metrics_seconds},
      {"writing", write_seconds},
      {"export", export_seconds},
      {"export_wait", export_wait_seconds},
      {"plots", plot_seconds}};
  WriteFileAtomic(out / "timing.json", timing.dump(2) + "\n");

  PrintClosingTable(scored.metrics, scored.results);
  std::printf(
      "\nrun: %.1f s simulated in %.1f s (real-time factor %.1fx): physics %.1f s, "
      "rendering %.1f s, pipelines %.2f s, metrics %.2f s, writing %.2f s, export %.1f s, plots "
      "%.1f s\n",
      sim_s, total, timing["real_time_factor"].get<double>(), physics_seconds, render_seconds,
      pipelines.seconds(), metrics_seconds, write_seconds, export_seconds, plot_seconds);
  std::printf(
      "wrote %s/{scenario.yaml, world.json, ground_truth.tum, <pipeline>.tum, "
      "<pipeline>_cov.txt, <pipeline>_errors.csv, metrics.json, timing.json, events.json%s}%s\n",
      out.string().c_str(), request.plots ? ", plots/" : "",
      request.export_dir ? (" and the dataset in " + request.export_dir->string()).c_str() : "");
  if (!simulation.path_done()) {
    std::printf("warning: the path was not finished (see events.json)\n");
  }
  if (plot_error) throw std::runtime_error(*plot_error);
  return scored.all_passed ? 0 : kExitExpectationsFailed;
}

}  // namespace corridorsim
