#include "harness/pipeline_runner.h"

#include <cstdio>
#include <utility>

#include "common/error.h"
#include "harness/run_folder.h"
#include "harness/stopwatch.h"

namespace corridorsim {
struct PipelineRunner::Run {
  std::unique_ptr<slam::Pipeline> pipeline;
  std::set<std::string> cameras;
  double seconds = 0.0;  // wall time inside the pipeline
};

PipelineRunner::PipelineRunner(const Scenario& scenario, const slam::Calibration& calibration) {
  for (const Scenario::PipelineEntry& entry : scenario.pipelines) {
    if (!entry.enabled) continue;
    Run run;
    run.pipeline = entry.options->Create(calibration);
    PipelineRecord record;
    record.name = entry.name;
    record.cameras_used = run.pipeline->cameras_used();
    for (const std::string& id : record.cameras_used) {
      if (!calibration.Find(id)) {
        throw LocateProblem(scenario, "pipelines",
                            OptionsProblem{entry.name, "reads the camera '" + id +
                                                           "', which is not enabled in sensors:"});
      }
      run.cameras.insert(id);
      cameras_used_.insert(id);
    }
    runs_.push_back(std::move(run));
    records_.push_back(std::move(record));
  }
}

PipelineRunner::~PipelineRunner() = default;

std::string PipelineRunner::Names() const {
  std::string names;
  for (const PipelineRecord& r : records_) names += (names.empty() ? "" : ", ") + r.name;
  return names;
}

void PipelineRunner::Initialize(TimeNs stamp_ns, const SE2& world_from_robot) {
  for (Run& run : runs_) run.pipeline->Initialize(stamp_ns, world_from_robot);
}

void PipelineRunner::OnOdometry(const WheelOdometry& odometry) {
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    Run& run = runs_[i];
    const WallClock::time_point t0 = WallClock::now();
    run.pipeline->OnOdometry(odometry);
    const slam::PoseEstimate e = run.pipeline->Estimate();
    run.seconds += SecondsSince(t0);
    records_[i].estimates.push_back({odometry.stamp_ns, e.world_from_robot, e.covariance});
  }
}

void PipelineRunner::OnCameraSet(const CameraSet& set) {
  for (const CameraSlot& slot : set.cameras) {
    if (!slot.message || !cameras_used_.count(slot.camera_id)) continue;
    const sim::CameraMessage& message = *slot.message;
    // What a robot's camera driver delivers: the image and, for a depth camera, the depth.
    slam::CameraInput input;
    input.image = StampedImage{message.stamp_ns, slot.camera_id, message.frame.rgb};
    if (!message.frame.noisy_depth_m.data.empty()) {
      input.depth = StampedDepth{message.stamp_ns, slot.camera_id, message.frame.noisy_depth_m};
    }
    for (std::size_t i = 0; i < runs_.size(); ++i) {
      Run& run = runs_[i];
      if (!run.cameras.count(slot.camera_id)) continue;
      const WallClock::time_point t0 = WallClock::now();
      run.pipeline->OnCamera(input);
      run.seconds += SecondsSince(t0);
      for (slam::Detection& d : run.pipeline->TakeDetections()) {
        records_[i].detections.push_back(std::move(d));
      }
    }
  }
}

void PipelineRunner::Finish() {
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    slam::Pipeline& pipeline = *runs_[i].pipeline;
    PipelineRecord& record = records_[i];
    record.landmarks = pipeline.Landmarks();
    for (slam::Innovation& innovation : pipeline.TakeInnovations()) {
      record.innovations.push_back(innovation);
    }
    record.stage_seconds = pipeline.stage_seconds();
    record.health = pipeline.health();
  }
}

std::string PipelineRunner::ErrorsLine(const TruthRecorder& truth) const {
  std::string errors;
  for (const PipelineRecord& record : records_) {
    if (record.estimates.empty()) continue;
    const EstimateSample& e = record.estimates.back();
    if (const TruthPose* t = truth.At(e.stamp_ns)) {
      const double error_m =
          (e.world_from_robot.translation() - t->world_from_robot.translation()).norm();
      errors += record.name + " " + FormatFixed(error_m, 3) + " m  ";
    }
  }
  return errors;
}

void PipelineRunner::WriteMaps(const std::filesystem::path& dir) const {
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    const std::filesystem::path maps = dir / records_[i].name;
    if (!runs_[i].pipeline->WriteMaps(maps).empty()) {
      std::printf("  %s wrote maps to %s\n", records_[i].name.c_str(), maps.string().c_str());
    }
  }
}

double PipelineRunner::seconds() const {
  double total = 0.0;
  for (const Run& run : runs_) total += run.seconds;
  return total;
}

}  // namespace corridorsim
