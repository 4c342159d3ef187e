#include "harness/pipeline_runner.h"

#include <cmath>
#include <cstdio>
#include <future>
#include <optional>
#include <utility>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/random.h"
#include "harness/run_folder.h"
#include "harness/stopwatch.h"
#include "slam/features/door_plates.h"

namespace corridorsim {
namespace {

// The world point a rendered depth frame shows at `pixel` (nearest pixel centre), or nothing
// where the depth is invalid: exact truth for a corner detection (metrics/map.cpp).
std::optional<SeenPoint> SeenAt(const render::CameraFrame& frame, const CameraModel& model,
                                const Eigen::Vector2d& pixel) {
  const ImageF& depth = frame.depth_m;
  const long x = std::lround(pixel.x());
  const long y = std::lround(pixel.y());
  if (depth.data.empty() || x < 0 || y < 0 || x >= depth.width || y >= depth.height) {
    return std::nullopt;
  }
  const float z = depth.at(static_cast<int>(x), static_cast<int>(y));
  if (!(z > 0.0f)) return std::nullopt;
  const Eigen::Vector3d bearing =
      model.Unproject(Eigen::Vector2d(static_cast<double>(x), static_cast<double>(y)));
  if (!(bearing.z() > 0.0)) return std::nullopt;
  SeenPoint seen;
  seen.p_in_world = frame.world_from_camera * (bearing * (static_cast<double>(z) / bearing.z()));
  const std::size_t index = static_cast<std::size_t>(y) * depth.width + static_cast<std::size_t>(x);
  if (index < frame.instance.size()) seen.instance_id = frame.instance[index];
  return seen;
}

}  // namespace

struct PipelineRunner::Run {
  std::unique_ptr<slam::Pipeline> pipeline;
  std::set<std::string> cameras;
  double seconds = 0.0;      // wall time inside the pipeline
  double cpu_seconds = 0.0;  // CPU time of the threads that ran its calls, during them
};

PipelineRunner::PipelineRunner(const Scenario& scenario, const slam::Calibration& calibration,
                               std::uint64_t run_seed) {
  for (const render::CameraOptions& camera : scenario.rig.cameras) {
    true_models_.emplace(camera.id, camera.model);
  }
  for (const Scenario::PipelineEntry& entry : scenario.pipelines) {
    if (!entry.enabled) continue;
    Run run;
    // Each pipeline's random choices draw from a stream of its own (docs/architecture.md), of
    // the run's seed: `run --seed N` reseeds the pipelines with everything else.
    const std::uint64_t seed = RandomStream(run_seed, 0, "slam." + entry.name).NextU64();
    try {
      run.pipeline = entry.options->Create(calibration, seed);
    } catch (const slam::ModelFileError& e) {
      // A pipeline's trained models are input too: named at its models_dir (or its section).
      throw LocateProblem(scenario, "pipelines",
                          OptionsProblem{entry.name + ".models_dir", e.what()});
    }
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
    const double cpu0 = ThreadCpuSeconds();
    run.pipeline->OnOdometry(odometry);
    const slam::PoseEstimate e = run.pipeline->Estimate();
    run.cpu_seconds += ThreadCpuSeconds() - cpu0;
    run.seconds += SecondsSince(t0);
    wall_seconds_ += SecondsSince(t0);
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
    // The pipelines that read this camera process the frame concurrently (they share nothing;
    // each one's own state decides its output, so the outputs do not depend on the schedule),
    // then their detections are collected in scenario order.
    std::vector<std::size_t> readers;
    for (std::size_t i = 0; i < runs_.size(); ++i) {
      if (runs_[i].cameras.count(slot.camera_id)) readers.push_back(i);
    }
    const WallClock::time_point t_frame = WallClock::now();
    const auto process = [this, &input](std::size_t i) {
      const WallClock::time_point t0 = WallClock::now();
      const double cpu0 = ThreadCpuSeconds();
      runs_[i].pipeline->OnCamera(input);
      runs_[i].cpu_seconds += ThreadCpuSeconds() - cpu0;
      runs_[i].seconds += SecondsSince(t0);
    };
    std::vector<std::future<void>> others;
    for (std::size_t k = 1; k < readers.size(); ++k) {
      others.push_back(std::async(std::launch::async, process, readers[k]));
    }
    if (!readers.empty()) process(readers[0]);
    for (std::future<void>& f : others) f.get();  // rethrows a pipeline's exception here
    wall_seconds_ += SecondsSince(t_frame);
    for (const std::size_t i : readers) {
      for (slam::Detection& d : runs_[i].pipeline->TakeDetections()) {
        // The boundary of slam/: a detection without the fields its type needs is a bug.
        if (const std::optional<std::string> problem = slam::DetectionProblem(d)) {
          const std::string what = "pipeline '" + records_[i].name + "' reported a " +
                                   slam::LandmarkTypeName(d.type) + " detection that " + *problem;
          CheckOrDie(false, "PipelineRunner", what.c_str());
        }
        if (d.type == slam::LandmarkType::kCorner) {
          if (const std::optional<SeenPoint> seen =
                  SeenAt(message.frame, true_models_.at(slot.camera_id), d.pixel)) {
            records_[i].seen_points[records_[i].detections.size()] = *seen;
          }
        }
        records_[i].detections.push_back(std::move(d));
      }
    }
  }
}

void PipelineRunner::Finish() {
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    slam::Pipeline& pipeline = *runs_[i].pipeline;
    PipelineRecord& record = records_[i];
    const WallClock::time_point t0 = WallClock::now();
    const double cpu0 = ThreadCpuSeconds();
    pipeline.Finish();
    runs_[i].cpu_seconds += ThreadCpuSeconds() - cpu0;
    runs_[i].seconds += SecondsSince(t0);
    wall_seconds_ += SecondsSince(t0);
    for (slam::Detection& d : pipeline.TakeDetections()) record.detections.push_back(std::move(d));
    record.landmarks = pipeline.Landmarks();
    record.areas = pipeline.Areas();
    record.occupancy_map = pipeline.occupancy_map();
    for (slam::Innovation& innovation : pipeline.TakeInnovations()) {
      record.innovations.push_back(innovation);
    }
    record.stage_seconds = pipeline.stage_seconds();
    record.cpu_seconds = runs_[i].cpu_seconds;
    record.health = pipeline.health();
  }
}

std::vector<PipelineRunner::Latest> PipelineRunner::LatestEstimates() const {
  std::vector<Latest> latest;
  for (const PipelineRecord& record : records_) {
    if (record.estimates.empty()) continue;
    const EstimateSample& e = record.estimates.back();
    latest.push_back({record.name, e.stamp_ns, e.world_from_robot.translation()});
  }
  return latest;
}

std::string PipelineRunner::ErrorsLine(const std::vector<Latest>& latest,
                                       const TruthRecorder& truth) {
  std::string errors;
  for (const Latest& e : latest) {
    if (const TruthPose* t = truth.At(e.stamp_ns)) {
      const double error_m = (e.position - t->world_from_robot.translation()).norm();
      errors += e.name + " " + FormatFixed(error_m, 3) + " m  ";
    }
  }
  return errors;
}

void PipelineRunner::WriteMaps(const std::filesystem::path& dir) {
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    records_[i].occupancy_map = nullptr;  // TakeMaps() may release it
    const std::vector<slam::MapFile> maps = runs_[i].pipeline->TakeMaps();
    if (maps.empty()) continue;
    std::filesystem::create_directories(dir);
    for (const slam::MapFile& map : maps) {
      WriteFileAtomic(dir / (records_[i].name + map.suffix), map.bytes);
    }
    std::printf("  %s wrote %zu map file%s to %s\n", records_[i].name.c_str(), maps.size(),
                maps.size() == 1 ? "" : "s", dir.string().c_str());
  }
}

double PipelineRunner::seconds() const { return wall_seconds_; }

}  // namespace corridorsim
