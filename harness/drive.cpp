#include "harness/drive.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <sstream>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/wheel_odometry_model.h"
#include "harness/frame_io.h"
#include "harness/progress.h"
#include "harness/run_io.h"
#include "harness/scenario.h"
#include "render/backend.h"
#include "render/camera_rig.h"
#include "render/scene.h"
#include "sim/simulation.h"
#include "worlds/image_io.h"

namespace corridorsim {
namespace {

std::string FormatFixed(double v) {
  char buf[40];
  std::snprintf(buf, sizeof(buf), "%.9f", v);
  return buf;
}

// Frames of one camera written as they come: images now, the per-frame truth at the end.
struct FrameWriter {
  std::filesystem::path dir;
  render::CameraOptions camera;
  nlohmann::ordered_json truth = nlohmann::ordered_json::array();

  void Write(const sim::CameraMessage& m) {
    char stamp[32];
    std::snprintf(stamp, sizeof(stamp), "%lld.%09lld",
                  static_cast<long long>(m.stamp_ns / kNanosecondsPerSecond),
                  static_cast<long long>(m.stamp_ns % kNanosecondsPerSecond));
    const std::string name = std::string(stamp) + ".png";
    const render::CameraFrame& f = m.frame;
    WriteFileAtomic(dir / "rgb" / name, EncodePng(f.rgb, name));
    WriteFileAtomic(dir / "labels" / name, EncodeLabels(f, f.rgb.width, f.rgb.height));
    if (camera.depth) WriteFileAtomic(dir / "depth" / name, EncodeDepth(f.noisy_depth_m, name));
    nlohmann::ordered_json j;
    j["t"] = stamp;
    j["frame_index"] = m.frame_index;
    j["world_from_camera"] = PoseJson(f.world_from_camera);
    j["truth"] = render::FrameTruthJson(m.truth);
    truth.push_back(std::move(j));
  }
};

}  // namespace

void RunDrive(const DriveRequest& request) {
  const Scenario scenario = LoadScenario(request.scenario_file);
  const render::BackendKind backend_kind = ChooseBackend(scenario.rig.backend);
  const std::filesystem::path& out = request.out_dir;
  EnsureOutputDirectory(out, "--out");
  const std::uint64_t seed = request.seed.value_or(scenario.seed);
  const worlds::World world = GenerateWorld(scenario, seed);
  sim::RobotPath path = BuildScenarioRobotPath(scenario, world);
  const SE2 start = path.world_from_start;

  // Rendering only when frames are saved: nothing else consumes them in a drive.
  std::optional<render::Scene> scene;
  std::unique_ptr<render::Backend> backend;
  std::unique_ptr<render::Rig> rig;
  std::vector<FrameWriter> writers;
  if (request.save_frames) {
    if (auto problem = render::CheckCameraPlacement(world, scenario.rig, SE3::FromSE2(start))) {
      throw LocateProblem(scenario, "sensors", *problem);
    }
    scene = render::BuildScene(world, scenario.rig.scene);
    backend = render::CreateBackend(backend_kind);
    backend->Upload(*scene);
    rig = std::make_unique<render::Rig>(scenario.rig, *scene, *backend);
    nlohmann::ordered_json intrinsics = nlohmann::ordered_json::object();
    for (const render::CameraRenderer& camera : rig->cameras()) {
      FrameWriter w{out / "frames" / camera.options().id, camera.options()};
      for (const char* sub : {"rgb", "labels", "depth"}) {
        if (std::string(sub) != "depth" || w.camera.depth)
          std::filesystem::create_directories(w.dir / sub);
      }
      intrinsics[camera.options().id] = IntrinsicsJson(camera.options());
      writers.push_back(std::move(w));
    }
    WriteFileAtomic(out / "frames" / "intrinsics.json", intrinsics.dump(2) + "\n");
  }

  sim::SimulationOptions options;
  options.robot = scenario.robot;
  options.robot_path = scenario.robot_path;
  options.seed = seed;
  options.max_duration_ns = FromSeconds(scenario.duration_s);
  sim::Simulation simulation(world, options, std::move(path), rig.get(), &scenario.rig);

  std::printf("drive: %s, seed %llu, path %s (%.1f m, %.0f deg of turns), physics %.0f Hz%s\n",
              scenario.name.empty() ? request.scenario_file.c_str() : scenario.name.c_str(),
              static_cast<unsigned long long>(seed),
              sim::PathKindName(scenario.robot_path.kind).c_str(), simulation.path().length_m(),
              simulation.path().total_turn_rad() * 180 / std::numbers::pi,
              scenario.robot.physics_rate_hz, request.save_frames ? ", rendering cameras" : "");

  std::ostringstream truth_tum, odometry_tum, odometry_csv;
  truth_tum << "# ground truth: world_from_robot (robot frame R: floor, between the wheels)\n"
            << "# timestamp tx ty tz qx qy qz qw\n";
  odometry_tum << "# wheel odometry dead reckoning (P1 eq. 13, nominal wheelbase) from the true "
                  "start pose\n# timestamp tx ty tz qx qy qz qw\n";
  odometry_csv << "timestamp_ns,left_distance_m,right_distance_m,left_ticks,right_ticks\n";
  const TimeNs truth_period = PeriodFromRateHz(kTruthFileRateHz);
  SE2 dead_reckoning = start;
  odometry_tum << sim::TumLine(0, SE3::FromSE2(dead_reckoning)) << "\n";
  truth_tum << sim::TumLine(0, simulation.truth().state.world_from_robot) << "\n";

  nlohmann::ordered_json events = nlohmann::ordered_json::array();
  int collisions = 0, slips = 0, frames = 0;
  double travelled_m = 0;
  Eigen::Vector3d last_position = simulation.truth().state.world_from_robot.translation();
  Progress progress("drive");
  while (!simulation.finished()) {
    const sim::StepOutput& step = simulation.Step();
    const TimeNs now = step.truth.stamp_ns;
    const Eigen::Vector3d position = step.truth.state.world_from_robot.translation();
    travelled_m += (position - last_position).head<2>().norm();
    last_position = position;
    if (now % truth_period == 0) {
      truth_tum << sim::TumLine(now, step.truth.state.world_from_robot) << "\n";
    }
    for (const WheelOdometry& o : step.odometry) {
      dead_reckoning = ApplyWheelOdometry(dead_reckoning, o.left_distance_m, o.right_distance_m,
                                          scenario.robot.wheelbase_m);
      if (o.stamp_ns == 0) continue;  // the start pose is already written
      odometry_tum << sim::TumLine(o.stamp_ns, SE3::FromSE2(dead_reckoning)) << "\n";
      odometry_csv << o.stamp_ns << "," << FormatFixed(o.left_distance_m) << ","
                   << FormatFixed(o.right_distance_m) << "," << o.left_ticks << "," << o.right_ticks
                   << "\n";
    }
    for (const sim::CameraMessage& m : step.frames) {
      writers[m.camera].Write(m);
      ++frames;
    }
    for (const sim::Event& e : step.events) {
      collisions += e.kind == sim::EventKind::kCollisionBegin;
      slips += e.kind == sim::EventKind::kSlip;
      events.push_back(EventJson(e));
    }
    progress.Update(now, simulation.progress(), "");
  }
  progress.Finish();
  if (simulation.now_ns() % truth_period != 0) {
    truth_tum << sim::TumLine(simulation.now_ns(), simulation.truth().state.world_from_robot)
              << "\n";
  }

  WriteFileAtomic(out / "ground_truth.tum", truth_tum.str());
  WriteFileAtomic(out / "odometry.tum", odometry_tum.str());
  WriteFileAtomic(out / "odometry.csv", odometry_csv.str());
  nlohmann::ordered_json events_json;
  events_json["seed"] = seed;
  events_json["duration_s"] = ToSeconds(simulation.now_ns());
  events_json["events"] = std::move(events);
  WriteFileAtomic(out / "events.json", events_json.dump(2) + "\n");
  for (const FrameWriter& w : writers) {
    WriteFileAtomic(w.dir / "frames.json", w.truth.dump(1) + "\n");
  }

  const SE2 truth_end = simulation.truth().world_from_robot_2d;
  const double wall = progress.wall_s();
  const double sim_s = ToSeconds(simulation.now_ns());
  std::printf("drive: %.1f s simulated in %.1f s (real-time factor %.1fx), %.2f m driven\n", sim_s,
              wall, wall > 0 ? sim_s / wall : 0.0, travelled_m);
  std::printf(
      "  end: truth (%.3f, %.3f, %.1f deg), %.3f m from the start; odometry off by %.3f m, "
      "%.2f deg\n",
      truth_end.x(), truth_end.y(), truth_end.yaw() * 180 / std::numbers::pi,
      (truth_end.translation() - start.translation()).norm(),
      (dead_reckoning.translation() - truth_end.translation()).norm(),
      std::abs(NormalizeAngle(dead_reckoning.yaw() - truth_end.yaw())) * 180 / std::numbers::pi);
  std::printf("  collisions %d, slips %d, frames %d%s\n", collisions, slips, frames,
              simulation.path_done() ? "" : "  (the path was not finished: see events.json)");
  std::printf("wrote %s/{ground_truth.tum, odometry.tum, odometry.csv, events.json%s}\n",
              out.string().c_str(), request.save_frames ? ", frames/" : "");
}

}  // namespace corridorsim
