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
#include <optional>
#include <string>
#include <vector>

#include "common/io/mcap.h"
#include "harness/metrics/input.h"
#include "harness/record/bag_writer.h"
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
  bool mcap = true;                     // false: no MCAP file (--record-bag alone)
  std::filesystem::path bag_file = {};  // --record-bag: the same topics as a ROS 1 bag ("": none)
};

class Recorder : public BusConsumer {
 public:
  /// Opens `file` (the MCAP, unless options.mcap is false) and options.bag_file (throws
  /// std::runtime_error when it cannot) and writes the metadata (MCAP only), the static
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

  std::uint64_t bytes() const {
    return (writer_ ? writer_->bytes_written() : 0) + (bag_ ? bag_->bytes() : 0);
  }
  /// Seconds on the bus thread (encoding) and on the writers' threads (compressing, writing).
  double encode_seconds() const { return encode_seconds_; }
  double compress_seconds() const {
    return (writer_ ? writer_->busy_seconds() : 0.0) + (bag_ ? bag_->busy_seconds() : 0.0);
  }

 private:
  template <ros::Message T>
  void Write(const std::string& topic, TimeNs stamp_ns, const T& message);
  void WriteMcapHeader(const std::filesystem::path& file, const RecordOptions& options,
                       const RecordingInfo& info);
  void WriteTruth(const sim::TruthSample& truth, std::uint8_t kind);
  void WriteStatic(const render::RigOptions& rig, const std::vector<sim::ImuOptions>& imus,
                   const std::vector<sim::LaserOptions>& lasers, const worlds::World& world);

  std::optional<mcap::Writer> writer_;
  std::optional<BagWriter> bag_;
  TopicFilter filter_;
  std::map<std::string, std::uint16_t> schemas_;   // type -> id
  std::map<std::string, std::uint16_t> channels_;  // topic -> id
  std::vector<std::string> camera_ids_;
  std::vector<CameraModel> camera_models_;  // per rendered camera
  std::vector<std::string> imu_ids_, laser_ids_;
  double wheelbase_m_ = 0.0;
  SE2 odom_pose_;  // /odom: the wheel odometry dead-reckoned with the nominal wheelbase
  std::vector<std::uint8_t> cdr_buffer_;      // one message's CDR, its memory reused
  std::vector<std::uint16_t> narrow_labels_;  // a frame's instance ids in 16 bits
  double encode_seconds_ = 0.0;
  bool closed_ = false;
};

}  // namespace corridorsim::record
