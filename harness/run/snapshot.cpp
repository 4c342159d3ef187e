#include "harness/run/snapshot.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/stable_json.h"
#include "common/pose.h"
#include "harness/run/frame_io.h"
#include "harness/run/run_folder.h"
#include "harness/run/simulation_setup.h"
#include "harness/scenario/scenario.h"
#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "render/scene.h"
#include "sim/placement.h"
#include "worlds/image_io.h"
#include "worlds/world_io.h"

namespace corridorsim {

void RunSnapshot(const SnapshotRequest& request) {
  const Scenario scenario = LoadScenario(request.scenario_file, request.settings);
  const SE2 pose(request.x_m, request.y_m, request.yaw_deg * std::numbers::pi / 180.0);
  const render::BackendKind backend_kind = ChooseBackend(scenario.rig.backend);
  // Written into a staging folder that replaces --out whole at the end (harness/run/run_folder.h).
  const std::unique_ptr<StagedDirectory> folder =
      StageOutputFolder(request.out_dir, "--out", request.force, ScenarioInputs(scenario));
  const std::filesystem::path dir = folder->path();
  const std::uint64_t seed = request.seed.value_or(scenario.seed);
  const worlds::World world = GenerateWorld(scenario, seed);
  const SE3 world_from_robot = SE3::FromSE2(pose);
  // The robot at --pose, checked as a path of one pose: the chassis against the world's solids,
  // each camera inside the corridor or a room (sim/placement.h). A pose whose robot hits a wall
  // is the command line's fault; a body too large for any pose, or a camera mount, the
  // scenario's.
  if (auto placed = CheckPosePlacement(world, scenario, scenario.rig, pose)) {
    // A camera that is still out with every mount moved over the robot's centre: the robot is.
    render::RigOptions centred = scenario.rig;
    for (render::CameraOptions& c : centred.cameras) c.mount.x_m = c.mount.y_m = 0.0;
    if (placed->section == "sensors" && CheckPosePlacement(world, scenario, centred, pose)) {
      placed->section = "path";
    }
    if (placed->section == "path") {
      throw InputError(SourceLocation{"command line", 0, 0}, "--pose",
                       "the robot at (" + FormatFixed(request.x_m, 2) + ", " +
                           FormatFixed(request.y_m, 2) + ") m, yaw " +
                           FormatFixed(request.yaw_deg, 1) + " deg: " + placed->problem.message);
    }
    if (placed->section == "sensors") {
      placed->problem.message += " with the robot at --pose " + FormatFixed(request.x_m, 2) + "," +
                                 FormatFixed(request.y_m, 2) + "," +
                                 FormatFixed(request.yaw_deg, 1);
    }
    throw LocateProblem(scenario, placed->section, placed->problem);
  }

  const auto t0 = std::chrono::steady_clock::now();
  const Renderer renderer(world, scenario.rig, backend_kind);
  const render::Rig& rig = *renderer.rig;
  std::vector<render::CameraFrame> frames;
  renderer.rig->Render(world_from_robot, seed, 0, &frames);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

  nlohmann::ordered_json truth_json;
  truth_json["seed"] = seed;
  truth_json["world_from_robot"] = PoseJson(world_from_robot);
  truth_json["cameras"] = nlohmann::ordered_json::object();
  nlohmann::ordered_json intrinsics = nlohmann::ordered_json::object();
  std::printf("snapshot: %s backend, robot at (%.2f, %.2f) yaw %.1f deg, %zu cameras in %.0f ms\n",
              render::BackendName(backend_kind).c_str(), pose.x(), pose.y(),
              pose.yaw() * 180.0 / std::numbers::pi, frames.size(), ms);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const render::CameraFrame& frame = frames[k];
    const render::CameraOptions& options = rig.cameras()[k].options();
    const std::string& id = frame.camera_id;
    const render::FrameTruth truth = FrameTruthOf(world, options, frame, world_from_robot);
    truth_json["cameras"][id] = render::FrameTruthJson(truth);
    intrinsics[id] = IntrinsicsJson(options);

    WriteFileAtomic(dir / (id + "_rgb.png"), EncodePng(frame.rgb, id + "_rgb.png"));
    WriteFileAtomic(dir / (id + "_labels.png"),
                    EncodeLabels(frame, frame.rgb.width, frame.rgb.height));
    WriteFileAtomic(dir / (id + "_overlay.png"),
                    EncodePng(DrawOverlay(frame.rgb, truth), id + "_overlay.png"));
    if (options.depth) {
      WriteFileAtomic(dir / (id + "_depth.png"),
                      EncodeDepth(frame.noisy_depth_m, id + "_depth.png"));
    }
    std::printf("  %-8s %dx%d  plates %zu, lamps %zu, doors %zu, corners %zu%s\n", id.c_str(),
                frame.rgb.width, frame.rgb.height, truth.plates.size(), truth.lamps.size(),
                truth.doors.size(), truth.corners.size(), options.depth ? ", depth" : "");
  }
  WriteFileAtomic(dir / "frame_ground_truth.json", JsonFileText(truth_json));
  WriteFileAtomic(dir / "intrinsics.json", JsonFileText(intrinsics));
  folder->Commit();
  std::printf("wrote %s\n", folder->path().string().c_str());
}

}  // namespace corridorsim
