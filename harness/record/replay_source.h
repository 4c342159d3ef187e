#pragma once
// A recording as the stream of a run (`corridorsim replay`, docs/recordings.md): its messages
// go to the bus's consumers in the order the live run delivered them (the recorder wrote them in
// that order), rebuilt bit for bit from the recording's standard and corridorsim_msgs topics,
// with each frame's landmark truth computed again from the world and the frame's label images
// (as the simulation did). No physics and no rendering run.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "common/io/mcap.h"
#include "harness/record/recorder.h"
#include "harness/run/sensor_bus.h"
#include "render/camera_options.h"
#include "worlds/world.h"

namespace corridorsim::record {

class ReplaySource {
 public:
  /// Opens `file` and reads what the run was (RecordingInfo). Throws InputError (exit 2) for a
  /// file that is not an MCAP recording, a corrupt one (naming the record and offset), or one
  /// that no corridorsim run made (no corridorsim metadata or no truth topic).
  explicit ReplaySource(const std::filesystem::path& file);
  ~ReplaySource();

  const RecordingInfo& info() const { return info_; }
  bool truncated() const;

  /// Throws InputError naming the first camera, IMU or scanner (and its topic) that the
  /// pipelines read and the recording lacks.
  void Require(const std::set<std::string>& cameras, const std::vector<std::string>& imus,
               const std::vector<std::string>& lasers) const;

  /// Delivers the stream to `consumers` as the live bus did, ending with OnStepEnd(last).
  /// `rig`: the scenario's cameras (their models give each frame's truth); `imus`, `lasers`: the
  /// enabled sensors' ids in order; `progress` (may be null) sees every truth sample's step end.
  void Replay(const std::vector<BusConsumer*>& consumers, const worlds::World& world,
              const render::RigOptions& rig, const std::vector<std::string>& imus,
              const std::vector<std::string>& lasers, BusConsumer* progress);

  /// The stamp of the run's end (the live simulation's now_ns()) and whether its path was done.
  TimeNs end_ns() const { return end_ns_; }
  bool path_done() const { return path_done_; }
  /// The share of the recording's messages replayed so far (the progress line's).
  double fraction() const { return fraction_; }

 private:
  std::filesystem::path file_;
  std::unique_ptr<mcap::Reader> reader_;
  RecordingInfo info_;
  TimeNs end_ns_ = 0;
  bool path_done_ = false;
  double fraction_ = 0.0;
};

}  // namespace corridorsim::record
