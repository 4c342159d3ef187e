#pragma once
// The `external` pipeline type: any program as a pipeline, in lockstep over the protocol of
// docs/protocol.md (harness/external/protocol.h). To the runner it is one slam::Pipeline among
// the others; each call is a message the program answers before the next is sent, so its
// outputs do not depend on how fast it is. Whatever the program does wrong (exits, crashes,
// stops answering, breaks the protocol, reports a non-finite estimate) throws from the call, and
// the runner fails this pipeline alone (harness/run/pipeline_runner.h) with the reason and the
// last lines the program printed; its output is kept as the run folder's <pipeline>.log.

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/options_table.h"
#include "harness/external/connection.h"
#include "harness/external/exchange_timing.h"
#include "harness/external/protocol.h"
#include "harness/external/reply_keys.h"
#include "slam/pipeline.h"
#include "slam/registry.h"

namespace corridorsim::external {

enum class ImageTransport { kSharedMemory, kInline };

/// `pipelines.<name>` of type `external`.
struct ExternalPipelineOptions {
  // The program and its arguments, never through a shell. argv[0] with a '/' is a path relative
  // to the file that sets it; without one it is searched on PATH (e.g. python3).
  std::vector<std::string> command;
  // The folder the program runs in: relative to the file that sets it; by default that file's.
  std::string working_dir;
  std::vector<std::string> cameras;  // the cameras it reads (rendered for it)
  double timeout_s = 60.0;           // longest wait for one reply (or for it to read a message)
  ImageTransport transport = ImageTransport::kSharedMemory;
  // The program's own options, passed to it as given, typed, in their order.
  nlohmann::ordered_json options = nlohmann::ordered_json::object();
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<ExternalPipelineOptions>& ExternalPipelineOptionsTable();

/// Longest timeout_s (a day): the bound on any wait for a program.
inline constexpr double kMaxTimeoutSeconds = 86400.0;
/// Arguments of a command at most, and bytes of one.
inline constexpr std::size_t kMaxCommandArgs = 256;
inline constexpr std::size_t kMaxArgumentBytes = 4096;

/// What an external pipeline's results depend on besides its options (provenance.json, a study's
/// plan): {"command": argv, "working_dir", "files": [{"argument", "path", "sha256"}]} with the
/// SHA-256 of every argument that names a regular file (argv[0] searched on PATH when it has no
/// '/', the others relative to working_dir): the interpreter and the script of `[python3,
/// my_slam.py]`. A file larger than kMaxFingerprintBytes has "sha256": null.
inline constexpr std::uint64_t kMaxFingerprintBytes = 256ull << 20;
nlohmann::ordered_json ProgramFingerprint(const ExternalPipelineOptions& options);

/// The `external` type, added to the registry by RegisterExternalPipelineType().
slam::PipelineType ExternalPipelineType();
/// Adds `external` to the pipeline types (once; later calls do nothing).
void RegisterExternalPipelineType();

/// One camera of a camera set as the runner hands it over: its input, or null when dropped.
struct SetFrame {
  std::string camera_id;
  const slam::CameraInput* input = nullptr;
};

class ExternalPipeline : public slam::Pipeline {
 public:
  /// Starts the program (throws StartError when it cannot be started: the scenario's fault).
  ExternalPipeline(const ExternalPipelineOptions& options, const slam::Calibration& calibration,
                   std::uint64_t seed);
  ~ExternalPipeline() override;

  /// The pipeline's name in the scenario, for the start message (the runner sets it).
  void set_name(std::string name) { name_ = std::move(name); }
  std::vector<std::string> cameras_used() const override { return options_.cameras; }
  void Initialize(TimeNs stamp_ns, const SE2& world_from_robot) override;
  void OnOdometry(const WheelOdometry& odometry) override;
  /// A frame on its own: sent as a set of one.
  void OnCamera(const slam::CameraInput& input) override;
  /// The frames of one camera set this pipeline reads (the runner calls this rather than
  /// OnCamera), dropped ones included.
  void OnCameraSet(TimeNs stamp_ns, const std::vector<SetFrame>& frames);
  /// Version 2 only: a sample of an IMU, a sweep of a scanner the program asked for in `ready`
  /// (others, and every one for a version-1 program, are not sent). IMU samples are sent in one
  /// imu message before the next message of another kind (or once kMaxImuBatch are held): the
  /// program gets them in bus order, a batch a round trip.
  void OnImu(const ImuSample& sample) override;
  void OnScan(const LaserScan& scan) override;
  /// What the program declared in its version-2 `ready` reply (Initialize read it).
  std::vector<slam::MeasurementType> measurement_types() const override {
    return ready_.measurement_types;
  }
  /// The protocol version the program speaks (1 until Initialize read its `ready`).
  int protocol() const { return ready_.protocol; }
  slam::PoseEstimate Estimate() const override { return estimate_; }
  std::vector<slam::LandmarkEstimate> Landmarks() const override { return landmarks_; }
  std::vector<slam::Detection> TakeDetections() override;
  std::vector<slam::Innovation> TakeInnovations() override;
  void Finish() override;
  std::vector<slam::MapFile> TakeMaps() override { return std::move(maps_); }
  std::map<std::string, double> stage_seconds() const override { return stage_seconds_; }
  slam::PipelineHealth health() const override { return health_; }

  /// What the program printed (ProgramConnection::Log), moved out; the program is ended first
  /// if it still runs (a failed pipeline's).
  std::string TakeLog();
  /// What was wrong with its replies but cost no result (a misspelt `stage_seconds`,
  /// reply_keys.h), each naming the message, moved out.
  std::vector<std::string> TakeWarnings();
  /// timing.json's `protocol` section (exchange_timing.h): the round trips, the program's reported
  /// and measured cost and `corridorsim_cpu_seconds`, this side's CPU time during the calls.
  /// Complete once TakeLog() ended the program.
  nlohmann::ordered_json ProtocolTiming(double corridorsim_cpu_seconds) const;

 private:
  // Sends a message and reads its reply; a failure ends the program and throws, naming the
  // message and with the program's last lines.
  Received Exchange(const nlohmann::ordered_json& message, std::string_view blob, int fd = -1);
  [[noreturn]] void FailWith(const std::string& what);
  // After a reply's results were kept: its warnings noted, and its errors fail the pipeline.
  void Keep(const char* message, const ReplyProblems& problems);
  // Reads the `processed` reply to a camera set, an IMU sample or a sweep (`cameras`: those whose
  // frames it may detect in; none for the others) and keeps its results.
  void KeepProcessed(const char* message, const Received& reply, TimeNs stamp_ns,
                     const std::vector<std::string>& cameras);
  // Sends the IMU samples held (one imu message) and reads its reply; nothing when none are.
  void FlushImu();
  std::chrono::duration<double> timeout() const;

  ExternalPipelineOptions options_;
  std::string name_;
  slam::Calibration calibration_;
  std::uint64_t seed_;
  std::unique_ptr<ProgramConnection> connection_;
  Ready ready_;  // what the program said in `ready`: its version, sensors, measurement types
  std::vector<ImuSample> imu_batch_;  // samples not sent yet (FlushImu)
  bool ended_ = false;                // the program was ended (finished or failed)
  // The shared memory of the images (ImageTransport::kSharedMemory).
  int memory_fd_ = -1;
  std::uint8_t* memory_ = nullptr;
  std::size_t memory_bytes_ = 0;
  // Each camera's fixed place in a camera set's images (its colour, then its depth, cameras in
  // `cameras` order): in the shared memory, and the bytes of all of them.
  std::map<std::string, std::size_t> image_offsets_;
  std::size_t set_bytes_ = 0;

  slam::PoseEstimate estimate_;
  std::vector<slam::Detection> detections_;
  std::vector<slam::Innovation> innovations_;
  std::vector<slam::LandmarkEstimate> landmarks_;
  std::vector<slam::MapFile> maps_;
  std::map<std::string, double> stage_seconds_;
  slam::PipelineHealth health_;
  std::string log_;
  std::vector<std::string> warnings_;
  ExchangeTimes times_;
  ProgramUsage usage_;
};

}  // namespace corridorsim::external
