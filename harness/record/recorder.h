#pragma once
// `--record`: the run's sensor stream, truth, estimates and world as an MCAP recording with ROS 2
// messages (docs/recordings.md). A consumer of the sensor bus like the others: it writes each
// message as the bus delivers it (so the file's data section is in delivery order, which replay
// relies on), the pipelines' estimates, paths and maps once they finished, and the run's scenario
// and provenance as metadata. Compression runs on the MCAP writer's own thread.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/io/mcap.h"
#include "harness/metrics/input.h"
#include "harness/record/ros_messages.h"
#include "harness/record/topics.h"
#include "harness/run/sensor_bus.h"
#include "render/camera_options.h"
#include "sim/imu.h"
#include "sim/laser_scanner.h"
#include "worlds/world.h"

namespace corridorsim::record {

/// What the recording says about its run: replay reads it back (recording_reader.h).
struct RecordingInfo {
  std::string scenario_file;
  std::string scenario_yaml;  // ResolvedScenarioYaml: the scenario as the run used it
  std::uint64_t seed = 0;
  std::vector<std::string> cameras;  // the rendered cameras, in the rig's order
  std::string provenance_json;
  std::string topics;  // --record-topics ("" for all)
};

struct RecordOptions {
  mcap::Compression compression = mcap::Compression::kZstd;
  TopicFilter topics;
};

class Recorder : public BusConsumer {
 public:
  /// Opens `file` (throws std::runtime_error when it cannot) and writes the metadata, the static
  /// transforms of every mount and the world's markers. `rig`: the rendered cameras enabled.
  Recorder(const std::filesystem::path& file, const RecordOptions& options,
           const RecordingInfo& info, const render::RigOptions& rig,
           const std::vector<sim::ImuOptions>& imus, const std::vector<sim::LaserOptions>& lasers,
           const worlds::World& world, double wheelbase_m);
  ~Recorder() override;

  void OnStart(const sim::TruthSample& truth) override;
  void OnTruth(const sim::TruthSample& truth) override;
  void OnOdometry(const WheelOdometry& odometry) override;
  void OnCameraSet(const CameraSet& set) override;
  void OnImu(const sim::ImuMessage& imu) override;
  void OnScan(const sim::ScanMessage& scan) override;
  void OnEvent(const sim::Event& event) override;
  void OnStepEnd(const sim::TruthSample& truth, bool last) override;

  /// Each pipeline's estimates (with covariance), its path and its final map, stamped as they
  /// were made; after the pipelines finished.
  void AddPipelines(const std::vector<PipelineRecord>& records);
  /// Writes the summary and closes the file (a recording without it is readable up to its last
  /// complete chunk).
  void Close();

  std::uint64_t bytes() const { return writer_.bytes_written(); }
  /// Seconds on the bus thread (encoding) and on the writer's thread (compressing, writing).
  double encode_seconds() const { return encode_seconds_; }
  double compress_seconds() const { return writer_.busy_seconds(); }

 private:
  template <ros::Message T>
  void Write(const std::string& topic, TimeNs stamp_ns, const T& message);
  void WriteTruth(const sim::TruthSample& truth, std::uint8_t kind);
  void WriteStatic(const render::RigOptions& rig, const std::vector<sim::ImuOptions>& imus,
                   const std::vector<sim::LaserOptions>& lasers, const worlds::World& world);

  mcap::Writer writer_;
  TopicFilter filter_;
  std::map<std::string, std::uint16_t> schemas_;   // type -> id
  std::map<std::string, std::uint16_t> channels_;  // topic -> id
  std::vector<std::string> camera_ids_;
  std::vector<CameraModel> camera_models_;  // per rendered camera
  std::vector<std::string> imu_ids_, laser_ids_;
  double wheelbase_m_ = 0.0;
  SE2 odom_pose_;  // /odom: the wheel odometry dead-reckoned with the nominal wheelbase
  double encode_seconds_ = 0.0;
  bool closed_ = false;
};

}  // namespace corridorsim::record
