#include "harness/run/run.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/stable_json.h"
#include "harness/record/recorder.h"
#include "harness/record/replay_scenario.h"
#include "harness/record/replay_source.h"
#include "harness/run/async_consumer.h"
#include "harness/run/export_consumer.h"
#include "harness/run/frame_keeper.h"
#include "harness/run/pipeline_runner.h"
#include "harness/run/progress.h"
#include "harness/run/provenance.h"
#include "harness/run/run_folder.h"
#include "harness/run/sensor_bus.h"
#include "harness/run/sensor_recorder.h"
#include "harness/run/simulation_setup.h"
#include "harness/run/stopwatch.h"
#include "harness/run/truth_recorder.h"
#include "harness/scenario/calibration.h"
#include "harness/scenario/scenario.h"

namespace corridorsim {
namespace {

// Camera sets queued for the pipelines' thread at most (a frame being rendered waits for room):
// two let the next frame render while the pipelines work on this one, and bound the memory of
// copied frames.
constexpr std::size_t kPipelineQueueFrames = 2;

// --export and --out are separate folders: neither may hold the other (each replaces its folder
// whole when committed).
void CheckSeparateFolders(const std::filesystem::path& out, const std::filesystem::path& dataset) {
  std::filesystem::path a, b;
  try {
    a = NormalOutputFolder(out);
    b = NormalOutputFolder(dataset);
  } catch (const std::runtime_error&) {
    return;  // StageOutputFolder reports the unusable one
  }
  std::error_code error;
  a = std::filesystem::weakly_canonical(a, error);
  b = std::filesystem::weakly_canonical(b, error);
  const auto within = [](const std::filesystem::path& outer, const std::filesystem::path& inner) {
    const auto [o, i] = std::mismatch(outer.begin(), outer.end(), inner.begin(), inner.end());
    return o == outer.end();
  };
  if (within(a, b) || within(b, a)) {
    throw InputError(SourceLocation{"command line", 0, 0}, "--export",
                     "'" + dataset.string() + "' and the run folder --out '" + out.string() +
                         "' must be separate folders (neither inside the other)");
  }
}

template <class Options>
std::vector<std::string> EnabledIds(const std::vector<Options>& sensors) {
  std::vector<std::string> ids;
  for (const Options& o : sensors) {
    if (o.enabled) ids.push_back(o.id);
  }
  return ids;
}

mcap::Compression RecordCompression(const std::string& name) {
  if (name == "zstd") return mcap::Compression::kZstd;
  if (name == "lz4") return mcap::Compression::kLz4;
  if (name == "none") return mcap::Compression::kNone;
  throw InputError(SourceLocation{"command line", 0, 0}, "--record-compression",
                   "'" + name + "' is not one of zstd, lz4, none");
}

}  // namespace

// Build, loop, finish (docs/architecture.md, "How a run is made").
int RunScenario(const RunRequest& request) {
  const WallClock::time_point run_start = WallClock::now();
  // A replay reads its stream from a recording (harness/record/replay_source.h) instead of the
  // simulation; everything else is the live run's, so the two write the same files.
  std::unique_ptr<record::ReplaySource> replay;
  if (request.replay) replay = std::make_unique<record::ReplaySource>(*request.replay);
  const Scenario scenario =
      replay ? record::ReplayScenario(replay->info(), request.replay->string(),
                                      request.scenario_file, request.settings, request.seed)
             : LoadScenario(request.scenario_file, request.settings);
  const record::RecordOptions record_options{
      RecordCompression(request.record_compression),
      request.record_topics.empty()
          ? record::TopicFilter()
          : record::TopicFilter(request.record_topics, "--record-topics")};
  const std::vector<Expectation> expectations = ScenarioExpectations(scenario);
  if (replay && request.export_dir) {
    throw InputError(SourceLocation{"command line", 0, 0}, "--export",
                     "a replay has no dataset to export (export from the live run)");
  }
  if (!request.export_dir) RequireScoredPipeline(scenario);  // else a run would score nothing
  // Output folders are checked and staged before anything runs: a run never ends unable to
  // write, and never leaves a folder with files of two runs.
  std::unique_ptr<StagedDirectory> out, dataset;
  if (!request.check_only) {
    std::vector<JobInput> inputs = ScenarioInputs(scenario);
    if (request.replay) inputs.push_back({*request.replay, "the recording"});
    if (request.export_dir) CheckSeparateFolders(request.out_dir, *request.export_dir);
    out = StageOutputFolder(request.out_dir, "--out", request.force, inputs);
    if (request.export_dir)
      dataset = StageOutputFolder(*request.export_dir, "--export", request.force, inputs);
  }

  // Build: the pipelines (all on the same stream), then the world, path and cameras they need.
  SimulationSetup setup(scenario,
                        replay ? replay->info().seed : request.seed.value_or(scenario.seed),
                        /*check_camera_placement=*/true);
  PipelineRunner pipelines(scenario, CalibrationOf(scenario), setup.seed());
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
  const std::vector<std::string> imu_ids = EnabledIds(scenario.imus);
  const std::vector<std::string> laser_ids = EnabledIds(scenario.lasers);
  if (replay) {
    replay->Require(pipelines.cameras_used(), imu_ids, laser_ids);
  } else {
    setup.Start(render_cameras);
  }
  sim::Simulation* simulation = replay ? nullptr : &setup.simulation();
  const std::vector<std::string> camera_ids = replay ? replay->info().cameras : setup.camera_ids();
  // The cameras of the stream: the rendered ones, or the recorded ones.
  render::RigOptions stream_rig = scenario.rig;
  for (render::CameraOptions& c : stream_rig.cameras) {
    c.enabled = std::find(camera_ids.begin(), camera_ids.end(), c.id) != camera_ids.end();
  }
  std::optional<ExportConsumer> exporter;
  if (dataset) {
    exporter.emplace(dataset->path(), setup.rig_options(), scenario.robot.wheelbase_m,
                     scenario.imus, scenario.lasers);
  }
  const char* job = replay ? "replay" : "run";
  std::printf("%s: %s, seed %llu, %zu pipeline(s)%s, path %s (%.1f m)%s\n", job,
              scenario.name.empty() ? scenario.file.c_str() : scenario.name.c_str(),
              static_cast<unsigned long long>(setup.seed()), pipelines.size(),
              pipelines.size() ? (": " + pipelines.Names()).c_str() : "",
              sim::PathKindName(scenario.robot_path.kind).c_str(), setup.robot_path().length_m(),
              replay ? (", from " + request.replay->string()).c_str()
                     : (camera_ids.empty() ? "" : ", rendering cameras"));

  // Loop: the simulation publishes, the consumers listen.
  TruthRecorder truth(pipelines.cameras_used());
  EventLog events;
  // Pipelines that read cameras run on a thread of their own, a frame or two behind the loop, so
  // that the next frames render while they work (harness/run/async_consumer.h: the same calls in
  // the same order, the same bytes); the progress line then reads a snapshot of their latest
  // estimates. Without cameras they run inline: handing every odometry message and physics step
  // to a thread would cost more than the pipelines do.
  std::mutex latest_mutex;
  std::vector<PipelineRunner::Latest> latest;
  std::optional<AsyncConsumer> async_pipelines;
  if (!pipelines.cameras_used().empty()) {
    async_pipelines.emplace(pipelines, kPipelineQueueFrames, [&] {
      std::vector<PipelineRunner::Latest> now = pipelines.LatestEstimates();
      const std::lock_guard<std::mutex> lock(latest_mutex);
      latest = std::move(now);
    });
  }
  const auto errors_line = [&] {
    if (!async_pipelines) return PipelineRunner::ErrorsLine(pipelines.LatestEstimates(), truth);
    std::vector<PipelineRunner::Latest> copy;
    {
      const std::lock_guard<std::mutex> lock(latest_mutex);
      copy = latest;
    }
    return PipelineRunner::ErrorsLine(copy, truth);
  };
  std::optional<ProgressLine> progress;
  if (replay) {
    progress.emplace(
        job, [&] { return replay->fraction(); }, errors_line);
  } else {
    progress.emplace(job, *simulation, errors_line);
  }
  SensorBus bus(camera_ids);
  bus.Subscribe(&truth);
  SensorRecorder sensors(scenario.imus, scenario.lasers, out->path());
  if (!sensors.empty()) bus.Subscribe(&sensors);
  if (exporter) bus.Subscribe(&*exporter);
  std::optional<FrameKeeper> kept_frames;
  if (request.keep_frames) {
    kept_frames.emplace(static_cast<std::size_t>(request.keep_frames_budget_mb * 1e6));
    bus.Subscribe(&*kept_frames);
  }
  bus.Subscribe(async_pipelines ? static_cast<BusConsumer*>(&*async_pipelines) : &pipelines);
  bus.Subscribe(&events);
  std::optional<record::Recorder> recorder;
  if (request.record || request.record_bag) {
    record::RecordingInfo info;
    info.scenario_file = scenario.file;
    info.scenario_yaml = ResolvedScenarioYaml(scenario, setup.seed());
    info.seed = setup.seed();
    info.cameras = camera_ids;
    info.provenance_json = ProvenanceJson(scenario.file, info.scenario_yaml, setup.seed(),
                                          setup.backend(), scenario.plugins, {}, scenario.settings)
                               .dump();
    info.topics = request.record_topics;
    record::RecordOptions files = record_options;
    files.mcap = request.record;
    if (request.record_bag) files.bag_file = out->path() / "recording.bag";
    recorder.emplace(out->path() / "recording.mcap", files, info, stream_rig, scenario.imus,
                     scenario.lasers, setup.world(), scenario.robot.wheelbase_m);
    bus.Subscribe(&*recorder);
  }
  const WallClock::time_point loop_start = WallClock::now();
  if (replay) {
    replay->Replay(bus.consumers(), setup.world(), scenario.rig, imu_ids, laser_ids, &*progress);
  } else {
    bus.Subscribe(&*progress);
    bus.Run(*simulation);
  }
  if (async_pipelines) async_pipelines->Drain();
  const TimeNs end_ns = replay ? replay->end_ns() : simulation->now_ns();
  const bool path_done = replay ? replay->path_done() : simulation->path_done();

  // Finish: pipelines, then metrics (deterministic) and timing (wall clock) in separate files.
  pipelines.Finish();
  double record_seconds = 0.0;
  if (recorder) {
    const WallClock::time_point t_record = WallClock::now();
    recorder->AddPipelines(pipelines.records());
    recorder->Close();
    record_seconds = SecondsSince(t_record) + recorder->encode_seconds();
  }
  const std::vector<const PipelineRecord*> failed = pipelines.Failed();
  for (const PipelineRecord* record : failed) {
    events.AddPipelineFailure(record->failure->stamp_ns, record->name, record->failure->call,
                              record->failure->what);
  }
  const WallClock::time_point t_metrics = WallClock::now();
  MetricsInput input;
  input.world = &setup.world();
  input.truth = truth.poses();
  input.frames = truth.frames();
  input.pipelines = pipelines.records();
  input.timing.sim_seconds = ToSeconds(end_ns);
  ScoredRun scored = ScoreRun(input, expectations);
  const double metrics_seconds = SecondsSince(t_metrics);

  // Wall-clock cost by stage (physics = the simulation step minus its rendering), the whole run;
  // written with the results, and again with the extras' seconds once they ran.
  const double sim_s = ToSeconds(end_ns);
  const double render_seconds = replay ? 0.0 : simulation->render_seconds();
  const double physics_seconds = bus.step_seconds() - render_seconds;
  double write_seconds = 0.0, export_seconds = 0.0, export_wait_seconds = 0.0, plot_seconds = 0.0;
  double viewer_seconds = 0.0;
  double total = 0.0;
  nlohmann::ordered_json& timing = scored.timing;
  const auto timing_json = [&] {
    total = SecondsSince(run_start);
    timing["sim_seconds"] = sim_s;
    timing["wall_seconds"] = total;
    timing["real_time_factor"] = total > 0 ? sim_s / total : 0.0;
    timing["stages_seconds"] = {
        {"setup", std::chrono::duration<double>(loop_start - run_start).count()},
        {"physics", physics_seconds},
        {"rendering", render_seconds},
        {"pipelines", pipelines.seconds()},
        {"pipelines_wait", async_pipelines ? async_pipelines->wait_seconds() : 0.0},
        {"metrics", metrics_seconds},
        {"writing", write_seconds},
        {"export", export_seconds},
        {"export_wait", export_wait_seconds},
        {"plots", plot_seconds},
        {"viewer", viewer_seconds},
        {"recording", record_seconds}};
    nlohmann::ordered_json rounded = timing;
    RoundNumbers(rounded, json_steps::kSeconds);
    return JsonFileText(rounded);
  };

  // Results first (committed as one folder), then the extras: a failing extra costs only itself.
  const auto write_results = [&](const std::filesystem::path& folder) {
    const WallClock::time_point t_write = WallClock::now();
    WriteRunFolder(folder, scenario, setup.seed(), setup.world(), truth, pipelines, scored.metrics,
                   events.Json(setup.seed(), end_ns), setup.backend());
    sensors.Finish();
    write_seconds = SecondsSince(t_write);
    WriteFileAtomic(folder / "timing.json", timing_json());
  };
  bool plots_written = false;
  std::vector<RunExtra> extras;
  extras.push_back({"maps/", [&] { pipelines.WriteMaps(out->path() / "maps"); }});
  if (exporter) {
    extras.push_back({"--export dataset", [&] {
                        exporter->Finish();
                        export_seconds = exporter->busy_seconds();
                        export_wait_seconds = exporter->wait_seconds();
                        dataset->Commit();
                      }});
  }
  // plots/ and viewer.html, made by a script over the run folder: timed, and noted when written.
  using MakePage = std::optional<std::string> (*)(const std::filesystem::path&);
  const auto page_extra = [&](const char* name, MakePage make, double* seconds, bool* written) {
    return RunExtra{name, [&out, make, seconds, written] {
                      const WallClock::time_point t_start = WallClock::now();
                      const std::optional<std::string> error = make(out->path());
                      *seconds = SecondsSince(t_start);
                      if (error) throw std::runtime_error(*error);
                      *written = true;
                    }};
  };
  if (request.plots) {
    extras.push_back(page_extra("plots/", &MakePlots, &plot_seconds, &plots_written));
  }
  if (kept_frames) {
    extras.push_back({"frames/", [&] { kept_frames->Write(out->path() / "frames"); }});
  }
  bool viewer_written = false;
  if (request.viewer) {
    // After plots/ and before timing.json's last write: the page shows the run's timing.
    extras.push_back(page_extra("viewer.html", &MakeViewer, &viewer_seconds, &viewer_written));
  }
  extras.push_back(
      {"timing.json", [&] { WriteFileAtomic(out->path() / "timing.json", timing_json()); }});
  const int extras_failed = CommitResultsThenExtras(*out, write_results, extras);

  PrintClosingTable(scored.metrics, scored.results, failed);
  std::printf(
      "\n%s: %.1f s simulated in %.1f s (real-time factor %.1fx): physics %.1f s, "
      "rendering %.1f s, pipelines %.2f s, metrics %.2f s, writing %.2f s, export %.1f s, plots "
      "%.1f s\n",
      job, sim_s, total, timing["real_time_factor"].get<double>(), physics_seconds, render_seconds,
      pipelines.seconds(), metrics_seconds, write_seconds, export_seconds, plot_seconds);
  std::printf(
      "wrote %s/{scenario.yaml, world.json, ground_truth.tum, <pipeline>.tum, "
      "<pipeline>_cov.txt, <pipeline>_errors.csv, <pipeline>_nis.csv, <pipeline>_landmarks.json, "
      "<pipeline>_detections.csv, metrics.json, timing.json, events.json, "
      "provenance.json%s%s%s%s%s}%s\n",
      out->path().string().c_str(), sensors.empty() ? "" : ", sensors/",
      request.record ? ", recording.mcap" : "", request.record_bag ? ", recording.bag" : "",
      plots_written ? ", plots/" : "", viewer_written ? ", viewer.html" : "",
      dataset && dataset->committed() ? (" and the dataset in " + dataset->path().string()).c_str()
                                      : "");
  if (!path_done) {
    std::printf("warning: the path was not finished (see events.json)\n");
  }
  if (extras_failed > 0) {
    std::printf("warning: %d extra(s) failed (see the messages above); the results are written\n",
                extras_failed);
  }
  for (const PipelineRecord& record : pipelines.records()) {
    for (const std::string& warning : record.warnings) {
      std::fprintf(stderr, "corridorsim: warning: pipeline '%s': %s\n", record.name.c_str(),
                   warning.c_str());
    }
  }
  for (const PipelineRecord* record : failed) {
    std::fprintf(stderr,
                 "corridorsim: pipeline '%s' failed at t = %.3f s: %s threw: %s (the other "
                 "pipelines' results are written; events.json)\n",
                 record->name.c_str(), ToSeconds(record->failure->stamp_ns),
                 record->failure->call.c_str(), record->failure->what.c_str());
  }
  return RunExitCode(scored.all_passed, extras_failed, !failed.empty());
}

}  // namespace corridorsim
