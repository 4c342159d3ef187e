#include "harness/run/drive.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>

#include "common/io/atomic_file.h"
#include "common/io/stable_json.h"
#include "common/wheel_odometry_model.h"
#include "harness/run/frame_writer.h"
#include "harness/run/progress.h"
#include "harness/run/provenance.h"
#include "harness/run/run_folder.h"
#include "harness/run/sensor_bus.h"
#include "harness/run/sensor_recorder.h"
#include "harness/run/simulation_setup.h"
#include "harness/run/truth_recorder.h"
#include "harness/scenario/scenario.h"

namespace corridorsim {
namespace {

// The raw odometry messages (CSV) and their dead reckoning (P1 eq. 13 with the nominal
// wheelbase) from the true start pose (TUM), as a robot's own odometry would report them.
class OdometryLog : public BusConsumer {
 public:
  OdometryLog(const SE2& start, double wheelbase_m) : pose_(start), wheelbase_m_(wheelbase_m) {
    tum_ << "# wheel odometry dead reckoning (P1 eq. 13, nominal wheelbase) from the true "
            "start pose\n# timestamp tx ty tz qx qy qz qw\n";
    tum_ << sim::TumLine(0, SE3::FromSE2(pose_)) << "\n";
    csv_ << "timestamp_ns,left_distance_m,right_distance_m,left_ticks,right_ticks\n";
  }
  void OnOdometry(const WheelOdometry& o) override {
    pose_ = ApplyWheelOdometry(pose_, o.left_distance_m, o.right_distance_m, wheelbase_m_);
    if (o.stamp_ns == 0) return;  // the start pose is already written
    tum_ << sim::TumLine(o.stamp_ns, SE3::FromSE2(pose_)) << "\n";
    csv_ << o.stamp_ns << "," << FormatFixed(o.left_distance_m, 9) << ","
         << FormatFixed(o.right_distance_m, 9) << "," << o.left_ticks << "," << o.right_ticks
         << "\n";
  }
  const SE2& pose() const { return pose_; }
  std::string tum() const { return tum_.str(); }
  std::string csv() const { return csv_.str(); }

 private:
  SE2 pose_;
  double wheelbase_m_;
  std::ostringstream tum_, csv_;
};

// Distance driven by the true robot (planar, summed per physics step).
class Odometer : public BusConsumer {
 public:
  void OnStart(const sim::TruthSample& truth) override {
    last_ = truth.state.world_from_robot.translation();
  }
  void OnStepEnd(const sim::TruthSample& truth, bool last) override {
    (void)last;
    const Eigen::Vector3d position = truth.state.world_from_robot.translation();
    travelled_m_ += (position - last_).head<2>().norm();
    last_ = position;
  }
  double travelled_m() const { return travelled_m_; }

 private:
  Eigen::Vector3d last_ = Eigen::Vector3d::Zero();
  double travelled_m_ = 0.0;
};

}  // namespace

void RunDrive(const DriveRequest& request) {
  const Scenario scenario = LoadScenario(request.scenario_file, request.settings);
  // Written into a staging folder that replaces --out whole at the end (harness/run/run_folder.h).
  const std::unique_ptr<StagedDirectory> folder =
      StageOutputFolder(request.out_dir, "--out", request.force, ScenarioInputs(scenario));
  const std::filesystem::path out = folder->path();
  // Rendering only when frames are saved: nothing else consumes them in a drive.
  SimulationSetup setup(scenario, request.seed.value_or(scenario.seed), request.save_frames);
  std::set<std::string> render_cameras;
  if (request.save_frames) {
    for (const render::CameraOptions& c : scenario.rig.cameras) render_cameras.insert(c.id);
  }
  setup.Start(render_cameras);
  sim::Simulation& simulation = setup.simulation();
  const SE2 start = simulation.path().world_from_start;

  std::printf("drive: %s, seed %llu, path %s (%.1f m, %.0f deg of turns), physics %.0f Hz%s\n",
              scenario.name.empty() ? request.scenario_file.c_str() : scenario.name.c_str(),
              static_cast<unsigned long long>(setup.seed()),
              sim::PathKindName(scenario.robot_path.kind).c_str(), simulation.path().length_m(),
              simulation.path().total_turn_rad() * 180 / std::numbers::pi,
              scenario.robot.physics_rate_hz, request.save_frames ? ", rendering cameras" : "");

  TruthRecorder truth;
  EventLog events;
  OdometryLog odometry(start, scenario.robot.wheelbase_m);
  Odometer odometer;
  std::optional<FrameWriter> frames;
  if (request.save_frames) frames.emplace(out / "frames", setup.rig_options());
  ProgressLine progress("drive", simulation);
  SensorBus bus(setup.camera_ids());
  for (BusConsumer* consumer :
       std::initializer_list<BusConsumer*>{&truth, &events, &odometry, &odometer, &progress}) {
    bus.Subscribe(consumer);
  }
  if (frames) bus.Subscribe(&*frames);
  SensorRecorder sensors(scenario.imus, scenario.lasers, out);
  if (!sensors.empty()) bus.Subscribe(&sensors);
  bus.Run(simulation);

  // ground_truth.tum means what it means in a run folder (the planar truth the metrics score);
  // the physics' full 3D pose has a name of its own.
  WriteFileAtomic(out / "ground_truth.tum", truth.PlanarTum());
  WriteFileAtomic(out / "ground_truth_3d.tum", truth.FullPoseTum());
  WriteFileAtomic(out / "odometry.tum", odometry.tum());
  WriteFileAtomic(out / "odometry.csv", odometry.csv());
  WriteFileAtomic(out / "events.json", events.Json(setup.seed(), simulation.now_ns()));
  sensors.Finish();
  WriteFileAtomic(out / "provenance.json",
                  JsonFileText(ProvenanceJson(
                      scenario.file, ResolvedScenarioYaml(scenario, setup.seed()), setup.seed(),
                      setup.backend(), scenario.plugins, {}, scenario.settings)));
  if (frames) frames->Finish();
  folder->Commit();

  const SE2 truth_end = simulation.truth().world_from_robot_2d;
  const SE2& dead_reckoning = odometry.pose();
  const double wall = progress.wall_s();
  const double sim_s = ToSeconds(simulation.now_ns());
  std::printf("drive: %.1f s simulated in %.1f s (real-time factor %.1fx), %.2f m driven\n", sim_s,
              wall, wall > 0 ? sim_s / wall : 0.0, odometer.travelled_m());
  std::printf(
      "  end: truth (%.3f, %.3f, %.1f deg), %.3f m from the start; odometry off by %.3f m, "
      "%.2f deg\n",
      truth_end.x(), truth_end.y(), truth_end.yaw() * 180 / std::numbers::pi,
      (truth_end.translation() - start.translation()).norm(),
      (dead_reckoning.translation() - truth_end.translation()).norm(),
      std::abs(NormalizeAngle(dead_reckoning.yaw() - truth_end.yaw())) * 180 / std::numbers::pi);
  std::printf("  collisions %d, slips %d, frames %d%s\n",
              events.count(sim::EventKind::kCollisionBegin), events.count(sim::EventKind::kSlip),
              frames ? frames->frames_written() : 0,
              simulation.path_done() ? "" : "  (the path was not finished: see events.json)");
  std::printf(
      "wrote %s/{ground_truth.tum, ground_truth_3d.tum, odometry.tum, odometry.csv, "
      "provenance.json, "
      "events.json%s%s}\n",
      folder->path().string().c_str(), sensors.empty() ? "" : ", sensors/",
      request.save_frames ? ", frames/" : "");
}

}  // namespace corridorsim
