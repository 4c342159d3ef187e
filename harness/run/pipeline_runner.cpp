#include "harness/run/pipeline_runner.h"

#include <cmath>
#include <cstdio>
#include <future>
#include <optional>
#include <stdexcept>
#include <utility>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/yaml_reader.h"
#include "common/random.h"
#include "harness/external/external_pipeline.h"
#include "harness/run/run_folder.h"
#include "harness/run/stopwatch.h"
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

// An exception's text as a record keeps it: printable, at most 2000 bytes.
std::string ExceptionText(std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    return InputExcerpt(e.what(), 2000);
  } catch (...) {
    return "an exception that is not a std::exception";
  }
}

// The start of a failure's reason for the live line (where the reason says what went wrong):
// at most kLiveReasonBytes, cut at a character's start.
std::string LiveReason(const std::string& what) {
  if (what.size() <= PipelineRunner::kLiveReasonBytes) return what;
  std::size_t cut = PipelineRunner::kLiveReasonBytes;
  while (cut > 0 && (static_cast<unsigned char>(what[cut]) & 0xC0) == 0x80) --cut;
  return what.substr(0, cut) + "...";
}

}  // namespace

struct PipelineRunner::Run {
  std::unique_ptr<slam::Pipeline> pipeline;  // null when its construction threw
  // The pipeline as a program's (harness/external): it takes camera sets whole.
  external::ExternalPipeline* external = nullptr;
  bool failed = false;
  std::set<std::string> cameras;
  // The measurement types of its own it declared (slam::MeasurementType): name -> dof.
  std::map<std::string, int> measurement_dof;
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
    PipelineRecord record;
    record.name = entry.name;
    try {
      run.pipeline = entry.options->Create(calibration, seed);
      if (!run.pipeline) throw std::runtime_error("its factory returned no pipeline");
      run.external = dynamic_cast<external::ExternalPipeline*>(run.pipeline.get());
      if (run.external) run.external->set_name(entry.name);
      record.cameras_used = run.pipeline->cameras_used();
    } catch (const external::StartError& e) {
      // A program that cannot be started is the scenario's fault, like a missing file.
      throw LocateProblem(scenario, "pipelines", OptionsProblem{entry.name + ".command", e.what()});
    } catch (const slam::ModelFileError& e) {
      // A pipeline's trained models are input too: named at its models_dir (or its section).
      throw LocateProblem(scenario, "pipelines",
                          OptionsProblem{entry.name + ".models_dir", e.what()});
    } catch (...) {
      // Its constructor (or cameras_used) threw: it fails alone, before the run starts.
      run.failed = true;
      run.pipeline.reset();
      record.cameras_used.clear();
      record.failure = PipelineFailure{0, "create", ExceptionText(std::current_exception())};
    }
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

template <class F>
bool PipelineRunner::Guard(std::size_t i, const char* what, TimeNs stamp_ns, F&& call) {
  Run& run = runs_[i];
  if (run.failed) return false;
  try {
    call(*run.pipeline);
    return true;
  } catch (...) {
    run.failed = true;
    records_[i].failure = PipelineFailure{stamp_ns, what, ExceptionText(std::current_exception())};
    return false;
  }
}

std::vector<const PipelineRecord*> PipelineRunner::Failed() const {
  std::vector<const PipelineRecord*> failed;
  for (const PipelineRecord& r : records_) {
    if (r.failure) failed.push_back(&r);
  }
  return failed;
}

void PipelineRunner::Initialize(TimeNs stamp_ns, const SE2& world_from_robot) {
  last_stamp_ns_ = stamp_ns;
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    // Its measurement types of its own are asked once it started (a program declares them in
    // its `ready` reply, docs/protocol.md).
    Guard(i, "Initialize", stamp_ns, [&](slam::Pipeline& p) {
      p.Initialize(stamp_ns, world_from_robot);
      const std::vector<slam::MeasurementType> declared = p.measurement_types();
      if (const std::optional<std::string> problem = slam::MeasurementTypesProblem(declared)) {
        throw std::runtime_error("it " + *problem);
      }
      for (const slam::MeasurementType& t : declared) runs_[i].measurement_dof[t.name] = t.dof;
    });
  }
}

void PipelineRunner::OnOdometry(const WheelOdometry& odometry) {
  last_stamp_ns_ = odometry.stamp_ns;
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    Run& run = runs_[i];
    const WallClock::time_point t0 = WallClock::now();
    const double cpu0 = ThreadCpuSeconds();
    slam::PoseEstimate e;
    const bool ok = Guard(i, "OnOdometry", odometry.stamp_ns, [&](slam::Pipeline& p) {
      p.OnOdometry(odometry);
      e = p.Estimate();
    });
    run.cpu_seconds += ThreadCpuSeconds() - cpu0;
    run.seconds += SecondsSince(t0);
    wall_seconds_ += SecondsSince(t0);
    if (!ok && run.external) {
      // A program whose reply held the estimate and a mistake (an unknown key) failed with this
      // call, but the estimate arrived and is kept (its stamp is this message's only then).
      e = run.external->Estimate();
    }
    if (ok || (run.external && e.stamp_ns == odometry.stamp_ns)) {
      records_[i].estimates.push_back({odometry.stamp_ns, e.world_from_robot, e.covariance});
    }
    TakeInnovations(i, odometry.stamp_ns);
  }
}

template <class F>
void PipelineRunner::Timed(const char* what, TimeNs stamp_ns, F&& call) {
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    const WallClock::time_point t0 = WallClock::now();
    const double cpu0 = ThreadCpuSeconds();
    Guard(i, what, stamp_ns, call);
    runs_[i].cpu_seconds += ThreadCpuSeconds() - cpu0;
    runs_[i].seconds += SecondsSince(t0);
    wall_seconds_ += SecondsSince(t0);
    TakeInnovations(i, stamp_ns);
  }
}

void PipelineRunner::OnImu(const sim::ImuMessage& imu) {
  Timed("OnImu", imu.sample.stamp_ns, [&](slam::Pipeline& p) { p.OnImu(imu.sample); });
}

void PipelineRunner::OnScan(const sim::ScanMessage& scan) {
  Timed("OnScan", scan.scan.stamp_ns, [&](slam::Pipeline& p) { p.OnScan(scan.scan); });
}

void PipelineRunner::OnCameraSet(const CameraSet& set) {
  OnCameraSetWhole(set);
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
    last_stamp_ns_ = message.stamp_ns;
    std::vector<std::size_t> readers;
    for (std::size_t i = 0; i < runs_.size(); ++i) {
      if (!runs_[i].failed && !runs_[i].external && runs_[i].cameras.count(slot.camera_id)) {
        readers.push_back(i);
      }
    }
    const WallClock::time_point t_frame = WallClock::now();
    const auto process = [this, &input](std::size_t i) {
      const WallClock::time_point t0 = WallClock::now();
      const double cpu0 = ThreadCpuSeconds();
      // Each reader's own fields only: the concurrent calls share nothing.
      Guard(i, "OnCamera", input.image.stamp_ns, [&](slam::Pipeline& p) { p.OnCamera(input); });
      runs_[i].cpu_seconds += ThreadCpuSeconds() - cpu0;
      runs_[i].seconds += SecondsSince(t0);
    };
    std::vector<std::future<void>> others;
    for (std::size_t k = 1; k < readers.size(); ++k) {
      others.push_back(std::async(std::launch::async, process, readers[k]));
    }
    if (!readers.empty()) process(readers[0]);
    for (std::future<void>& f : others) f.get();  // Guard caught the pipelines' exceptions
    wall_seconds_ += SecondsSince(t_frame);
    for (const std::size_t i : readers) {
      TakeDetections(i, set, message.stamp_ns);
      TakeInnovations(i, message.stamp_ns);
    }
  }
}

void PipelineRunner::TakeDetections(std::size_t i, const CameraSet& set, TimeNs stamp_ns) {
  std::vector<slam::Detection> detections;
  if (runs_[i].external) {
    // A program's detections are checked replies held by harness code: they are taken even when
    // the reply that brought them failed the pipeline (what arrived is kept).
    detections = runs_[i].external->TakeDetections();
  } else {
    Guard(i, "TakeDetections", stamp_ns,
          [&](slam::Pipeline& p) { detections = p.TakeDetections(); });
  }
  for (slam::Detection& d : detections) {
    // The boundary of slam/: a detection without the fields its type needs, or of a camera
    // whose frame it was not given, is a bug of the pipeline, which fails it like an exception
    // would (a plugin's bug costs only itself).
    std::optional<std::string> problem = slam::DetectionProblem(d);
    const CameraSlot* slot = set.Find(d.camera_id);
    if (!problem && (!slot || !slot->message || !runs_[i].cameras.count(d.camera_id))) {
      problem = "is of the camera '" + d.camera_id + "', which gave it no frame at this stamp";
    }
    if (!problem) problem = MeasurementProblem(i, d.measurement, std::nullopt);
    if (problem) {
      runs_[i].failed = true;
      if (!records_[i].failure) {
        records_[i].failure = PipelineFailure{
            stamp_ns, "TakeDetections",
            "reported a " +
                InputExcerpt(slam::MeasurementName(d), slam::kMaxMeasurementNameLength) +
                " detection that " + InputExcerpt(*problem, 2000)};
      }
      return;
    }
    if (d.Is(slam::LandmarkType::kCorner)) {
      if (const std::optional<SeenPoint> seen =
              SeenAt(slot->message->frame, true_models_.at(d.camera_id), d.pixel)) {
        records_[i].seen_points[records_[i].detections.size()] = *seen;
      }
    }
    records_[i].detections.push_back(std::move(d));
  }
}

std::optional<std::string> PipelineRunner::MeasurementProblem(std::size_t i,
                                                              const std::string& measurement,
                                                              std::optional<int> dof) const {
  if (measurement.empty()) return std::nullopt;  // a shipped landmark type
  const std::map<std::string, int>& declared = runs_[i].measurement_dof;
  const auto it = declared.find(measurement);
  if (it != declared.end()) {
    if (!dof || *dof == it->second) return std::nullopt;
    return "has " + std::to_string(*dof) + " degrees of freedom, but the type was declared with " +
           std::to_string(it->second);
  }
  std::string names;
  for (const auto& [name, d] : declared) {
    names += (names.empty() ? "" : ", ") + name + " (" + std::to_string(d) + " dof)";
  }
  return "is of a measurement type it did not declare (Pipeline::measurement_types: " +
         (names.empty() ? std::string("none") : names) + ")";
}

void PipelineRunner::TakeInnovations(std::size_t i, TimeNs stamp_ns) {
  std::vector<slam::Innovation> innovations;
  if (runs_[i].external) {
    if (runs_[i].failed) return;  // KeepWhatArrived takes a failed program's
    innovations = runs_[i].external->TakeInnovations();
  } else {
    Guard(i, "TakeInnovations", stamp_ns,
          [&](slam::Pipeline& p) { innovations = p.TakeInnovations(); });
  }
  for (slam::Innovation& n : innovations) {
    if (const std::optional<std::string> problem = MeasurementProblem(i, n.measurement, n.dof)) {
      runs_[i].failed = true;
      if (!records_[i].failure) {
        records_[i].failure =
            PipelineFailure{stamp_ns, "TakeInnovations",
                            "reported an innovation of '" +
                                InputExcerpt(n.measurement, slam::kMaxMeasurementNameLength) +
                                "' that " + *problem};
      }
      return;
    }
    records_[i].innovations.push_back(std::move(n));
  }
}

void PipelineRunner::OnCameraSetWhole(const CameraSet& set) {
  // Pipelines that are programs take the cameras they read of a set in one message, dropped
  // frames included (docs/protocol.md); they run one after the other (each waits on its own
  // program, which runs in parallel with nothing else of this run).
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    Run& run = runs_[i];
    if (!run.external || run.failed) continue;
    std::vector<slam::CameraInput> inputs;
    std::vector<external::SetFrame> frames;
    inputs.reserve(set.cameras.size());
    for (const CameraSlot& slot : set.cameras) {
      if (!run.cameras.count(slot.camera_id)) continue;
      external::SetFrame frame{slot.camera_id, nullptr};
      if (slot.message) {
        const sim::CameraMessage& message = *slot.message;
        slam::CameraInput& input = inputs.emplace_back();
        input.image = StampedImage{message.stamp_ns, slot.camera_id, message.frame.rgb};
        if (!message.frame.noisy_depth_m.data.empty()) {
          input.depth = StampedDepth{message.stamp_ns, slot.camera_id, message.frame.noisy_depth_m};
        }
        frame.input = &input;
      }
      frames.push_back(frame);
    }
    if (frames.empty()) continue;
    last_stamp_ns_ = set.stamp_ns;
    const WallClock::time_point t0 = WallClock::now();
    const double cpu0 = ThreadCpuSeconds();
    Guard(i, "OnCameraSet", set.stamp_ns,
          [&](slam::Pipeline&) { run.external->OnCameraSet(set.stamp_ns, frames); });
    run.cpu_seconds += ThreadCpuSeconds() - cpu0;
    run.seconds += SecondsSince(t0);
    wall_seconds_ += SecondsSince(t0);
    TakeDetections(i, set, set.stamp_ns);
    TakeInnovations(i, set.stamp_ns);
  }
}

void PipelineRunner::Finish() {
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    PipelineRecord& record = records_[i];
    const WallClock::time_point t0 = WallClock::now();
    const double cpu0 = ThreadCpuSeconds();
    // One guarded call for the whole end of the run: a pipeline whose Finish() or any getter
    // throws is failed, and what it gave before stays in its record.
    Guard(i, "Finish", last_stamp_ns_, [&](slam::Pipeline& pipeline) {
      pipeline.Finish();
      for (slam::Detection& d : pipeline.TakeDetections()) {
        if (const std::optional<std::string> problem =
                MeasurementProblem(i, d.measurement, std::nullopt)) {
          throw std::runtime_error(
              "reported a " +
              InputExcerpt(slam::MeasurementName(d), slam::kMaxMeasurementNameLength) +
              " detection that " + *problem);
        }
        record.detections.push_back(std::move(d));
      }
      record.landmarks = pipeline.Landmarks();
      record.areas = pipeline.Areas();
      record.occupancy_map = pipeline.occupancy_map();
      record.stage_seconds = pipeline.stage_seconds();
      record.health = pipeline.health();
    });
    TakeInnovations(i, last_stamp_ns_);
    runs_[i].cpu_seconds += ThreadCpuSeconds() - cpu0;
    runs_[i].seconds += SecondsSince(t0);
    wall_seconds_ += SecondsSince(t0);
    record.cpu_seconds = runs_[i].cpu_seconds;
    if (record.failure) record.occupancy_map = nullptr;
    if (external::ExternalPipeline* program = runs_[i].external) {
      // A program's output, whether it finished or failed (it is ended now if it still runs).
      record.log = program->TakeLog();
      if (record.failure) KeepWhatArrived(*program, record);
      record.warnings = program->TakeWarnings();
      record.protocol_timing = program->ProtocolTiming(runs_[i].cpu_seconds);
    }
  }
}

void PipelineRunner::KeepWhatArrived(external::ExternalPipeline& program, PipelineRecord& record) {
  // A failed program's replies were checked before they were kept (harness/external), so what
  // they brought is safe to record: the detections and innovations of the run so far, and of the
  // `finished` reply the parts that were right. Its metrics still say only that it failed.
  for (slam::Detection& d : program.TakeDetections()) record.detections.push_back(std::move(d));
  for (slam::Innovation& n : program.TakeInnovations()) record.innovations.push_back(n);
  if (record.landmarks.empty()) record.landmarks = program.Landmarks();
  if (record.stage_seconds.empty()) record.stage_seconds = program.stage_seconds();
}

std::vector<PipelineRunner::Latest> PipelineRunner::LatestEstimates() const {
  std::vector<Latest> latest;
  for (const PipelineRecord& record : records_) {
    if (record.failure) {
      // From the moment it fails: `failed` and why, never its last error as if it went on.
      Latest failed;
      failed.name = record.name;
      failed.failed = LiveReason(record.failure->what);
      latest.push_back(std::move(failed));
      continue;
    }
    if (record.estimates.empty()) continue;
    const EstimateSample& e = record.estimates.back();
    latest.push_back({record.name, e.stamp_ns, e.world_from_robot.translation(), {}});
  }
  return latest;
}

std::string PipelineRunner::ErrorsLine(const std::vector<Latest>& latest,
                                       const TruthRecorder& truth) {
  std::string errors;
  for (const Latest& e : latest) {
    if (!e.failed.empty()) {
      errors += e.name + " failed: " + e.failed + "  ";
      continue;
    }
    if (const TruthPose* t = truth.At(e.stamp_ns)) {
      const double error_m = (e.position - t->world_from_robot.translation()).norm();
      errors += e.name + " " + FormatFixed(error_m, 3) + " m  ";
    }
  }
  return errors;
}

void PipelineRunner::WriteMaps(const std::filesystem::path& dir) {
  std::string errors;
  for (std::size_t i = 0; i < runs_.size(); ++i) {
    records_[i].occupancy_map = nullptr;  // TakeMaps() may release it
    if (records_[i].failure) continue;    // a failed pipeline's maps are not written
    std::vector<slam::MapFile> maps;
    if (!Guard(i, "TakeMaps", last_stamp_ns_, [&](slam::Pipeline& p) { maps = p.TakeMaps(); })) {
      // After the results: the maps are an extra, and this costs only them (exit 4).
      errors += (errors.empty() ? "" : "; ") + std::string("pipeline '") + records_[i].name +
                "' threw from TakeMaps: " + records_[i].failure->what;
      continue;
    }
    if (maps.empty()) continue;
    std::filesystem::create_directories(dir);
    for (const slam::MapFile& map : maps) {
      WriteFileAtomic(dir / (records_[i].name + map.suffix), map.bytes);
    }
    std::printf("  %s wrote %zu map file%s to %s\n", records_[i].name.c_str(), maps.size(),
                maps.size() == 1 ? "" : "s", dir.string().c_str());
  }
  if (!errors.empty()) throw std::runtime_error(errors);
}

double PipelineRunner::seconds() const { return wall_seconds_; }

}  // namespace corridorsim
