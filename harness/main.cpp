// The corridorsim command. Subcommands: run (the main job), world, snapshot, drive. Exit
// codes: 0 success, 2 bad input (one message naming file, line and key), 1 any other failure.

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include <CLI/CLI.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "harness/drive.h"
#include "harness/job.h"
#include "harness/run.h"
#include "harness/scenario.h"
#include "harness/snapshot.h"
#include "worlds/world_io.h"

namespace corridorsim {
namespace {

constexpr int kExitBadInput = 2;

std::string DefaultScenarioPath() {
  if (std::filesystem::exists("scenarios/default.yaml")) return "scenarios/default.yaml";
  return std::string(CORRIDORSIM_SCENARIO_DIR) + "/default.yaml";
}

void PrintWorldSummary(const worlds::World& world, const std::filesystem::path& out, double ms) {
  std::map<std::string, int> door_states;
  for (const auto& d : world.doors) ++door_states[worlds::DoorStateName(d.state)];
  int circular = 0, off = 0, room_lamps = 0;
  for (const auto& l : world.lamps) {
    circular += l.shape == worlds::LampShape::kCircular;
    off += !l.on;
    room_lamps += l.room_door_id >= 0;
  }
  const Eigen::Vector3d size = world.bounds.sizes();
  std::printf("world: %s, seed %llu, %.1f x %.1f x %.1f m, generated in %.0f ms\n",
              worlds::LayoutName(world.options.layout).c_str(),
              static_cast<unsigned long long>(world.seed), size.x(), size.y(), size.z(), ms);
  std::printf("  corridor segments %zu, walls %zu\n", world.segments.size(), world.walls.size());
  std::printf("  doors %zu (closed %d, open %d, empty %d)\n", world.doors.size(),
              door_states["closed"], door_states["open"], door_states["empty"]);
  std::printf("  door plates %zu\n", world.plates.size());
  std::printf("  lamps %zu (circular %d, panel %zu, in rooms %d, off %d), reflectors %zu\n",
              world.lamps.size(), circular, world.lamps.size() - circular, room_lamps, off,
              world.reflectors.size());
  std::printf("  ceiling corner points %zu, distractors %zu\n", world.corner_points.size(),
              world.distractors.size());
  std::printf("  meshes %zu, triangles %zu, textures %zu, collision boxes %zu\n",
              world.meshes.size(), world.triangle_count(), world.textures.size(),
              world.collision_boxes.size());
  std::printf("wrote %s/{world.obj, world.mtl, textures/, ground_truth.json, map.png}\n",
              out.string().c_str());
}

int RunWorld(const JobRequest& request) {
  const Scenario scenario = LoadScenario(request.scenario_file);
  const std::filesystem::path& out = request.out_dir;
  EnsureOutputDirectory(out, "--out");
  const std::uint64_t world_seed = request.seed.value_or(scenario.seed);
  const auto t0 = std::chrono::steady_clock::now();
  const worlds::World world = GenerateWorld(scenario, world_seed);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  worlds::WriteWorldFiles(world, out);
  PrintWorldSummary(world, out, ms);
  return 0;
}

// The options of every scenario job: the scenario file, --seed and --out (its default shown in
// --help; `out` holds the folder's text until Resolve).
struct JobOptions {
  JobRequest* request;
  std::string out;

  JobOptions(CLI::App* job, JobRequest* r, std::string default_out, const char* scenario_help,
             const char* seed_help, const char* out_help)
      : request(r), out(std::move(default_out)) {
    job->add_option("scenario", request->scenario_file, scenario_help);
    job->add_option("--seed", request->seed, seed_help);
    job->add_option("--out", out, out_help)->capture_default_str();
  }
  // After parsing: the default scenario when none was given, the output folder.
  void Resolve() const {
    if (request->scenario_file.empty()) request->scenario_file = DefaultScenarioPath();
    request->out_dir = out;
  }
};

}  // namespace
}  // namespace corridorsim

int main(int argc, char** argv) {
  using namespace corridorsim;
  CLI::App app{"corridorsim: a simulation harness for corridor SLAM"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Show the help of every subcommand");

  JobRequest world_request;
  CLI::App* world = app.add_subcommand(
      "world", "Generate a corridor world and write its geometry, textures, ground truth and plan");
  const JobOptions world_options(
      world, &world_request, "out/world",
      "Scenario YAML whose `world:` section and `seed` are used (default: "
      "scenarios/default.yaml)",
      "Seed of the world's random streams (default: the scenario's `seed`)",
      "Output folder for world.obj, world.mtl, textures/, ground_truth.json, map.png");
  world->footer(
      "Writes world.obj + world.mtl + textures/*.png (open in MeshLab or Blender), "
      "ground_truth.json (door plates, lamps, doors, corridor segments, corner points, "
      "distractors; metres, world frame) and map.png (top-down plan).\n"
      "Exit codes: 0 success, 2 bad input (file:line:column: key: message), 1 other failures.");

  SnapshotRequest snapshot_request;
  CLI::App* snapshot = app.add_subcommand(
      "snapshot", "Place the robot at one pose and render every camera of the rig");
  const JobOptions snapshot_options(
      snapshot, &snapshot_request, "out/snapshot",
      "Scenario YAML (world, sensors, render); default: scenarios/default.yaml",
      "Seed of the world and the sensor noise", "Output folder");
  snapshot
      ->add_option("--pose", snapshot_request.pose_text,
                   "Robot pose x,y,yaw: metres in the world frame and degrees (0 = along +x)")
      ->required();
  snapshot->footer(
      "Writes per camera <camera>_rgb.png, <camera>_labels.png (16-bit RGB: R = semantic class, "
      "G = instance id >> 16, B = instance id & 0xffff), <camera>_overlay.png (ground truth drawn "
      "on the image), front_depth.png (16-bit, 5000 per metre, 0 = invalid), plus "
      "frame_ground_truth.json and intrinsics.json.\n"
      "Environment: CORRIDORSIM_RENDER_BACKEND=osmesa|egl overrides the scenario's "
      "render.backend.\n"
      "Exit codes: 0 success, 2 bad input, 1 other failures (e.g. no GL context).");

  RunRequest run_request;
  std::string run_export;
  bool no_plots = false;
  CLI::App* run = app.add_subcommand(
      "run",
      "Run a scenario closed loop, score every pipeline against ground truth, write the run");
  const JobOptions run_options(run, &run_request, "out/run",
                               "Scenario YAML (default: scenarios/default.yaml)",
                               "Seed of every random stream of the run", "Run folder");
  run->add_option("--export", run_export,
                  "Also write a dataset: TUM RGB-D (front), EuRoC/ASL (upward, lateral), "
                  "odometry CSV, labels and COCO plate boxes (docs/export.md)");
  run->add_flag("--no-plots", no_plots, "Skip plots/ (matplotlib)");
  run->add_flag("--check", run_request.check_only,
                "Only check the scenario: load it, build its world, path and pipelines, and exit");
  run->footer(
      "Writes scenario.yaml (resolved, with the seed), world.json, ground_truth.tum, "
      "<pipeline>.tum, <pipeline>_cov.txt (ov_eval), <pipeline>_errors.csv, metrics.json "
      "(docs/metrics.md), timing.json, events.json, maps/, plots/.\n"
      "Exit codes: 0 success, 3 an expectation failed, 2 bad input, 1 other failures.");

  DriveRequest drive_request;
  CLI::App* drive = app.add_subcommand(
      "drive", "Drive the scenario's path closed loop and write trajectories, odometry and events");
  const JobOptions drive_options(
      drive, &drive_request, "out/drive",
      "Scenario YAML (world, robot, path, sensors); default: scenarios/default.yaml",
      "Seed of the world, the odometry errors and the sensor noise", "Output folder");
  drive->add_flag("--save-frames", drive_request.save_frames,
                  "Render the cameras at their rates and write every frame");
  drive->footer(
      "Writes ground_truth.tum (world_from_robot at 100 Hz) and odometry.tum (wheel odometry dead "
      "reckoning from the true start pose), both TUM format: t x y z qx qy qz qw, seconds; "
      "odometry.csv (the raw messages: per-wheel distances and ticks); events.json (collisions, "
      "slips, path done or timeout). With --save-frames: frames/<camera>/{rgb,labels,depth}/"
      "<t>.png, frames/<camera>/frames.json (pose and visible landmarks per frame) and "
      "frames/intrinsics.json.\n"
      "Exit codes: 0 success, 2 bad input, 1 other failures.");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return kExitBadInput;
  }

  try {
    if (snapshot->parsed()) {
      snapshot_options.Resolve();
      RunSnapshot(snapshot_request);
      return 0;
    }
    if (run->parsed()) {
      run_options.Resolve();
      if (!run_export.empty()) run_request.export_dir = run_export;
      run_request.plots = !no_plots;
      return RunScenario(run_request);
    }
    if (drive->parsed()) {
      drive_options.Resolve();
      RunDrive(drive_request);
      return 0;
    }
    if (world->parsed()) {
      world_options.Resolve();
      return RunWorld(world_request);
    }
  } catch (const InputError& e) {
    std::fprintf(stderr, "corridorsim: error: %s\n", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "corridorsim: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
