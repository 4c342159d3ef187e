#pragma once
// Bus consumers that keep what the metrics and the run folder need of the ground truth: the
// robot's pose on the 100 Hz grid (TruthRecorder, with the camera frames' truth for detector
// scores) and the simulation's events (EventLog, events.json).

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/pose.h"
#include "harness/metrics.h"
#include "harness/sensor_bus.h"

namespace corridorsim {

class TruthRecorder : public BusConsumer {
 public:
  /// Keeps the truth of the frames of `frame_cameras` (the cameras some pipeline reads).
  explicit TruthRecorder(std::set<std::string> frame_cameras = {});

  void OnStart(const sim::TruthSample& truth) override;
  void OnCameraSet(const CameraSet& set) override;
  void OnStepEnd(const sim::TruthSample& truth, bool last) override;

  /// Planar truth at 0, every grid point (kTruthFileRateHz) and the run's last instant.
  const std::vector<TruthPose>& poses() const { return poses_; }
  const std::vector<FrameTruthSample>& frames() const { return frames_; }
  /// The truth at `stamp`: the last recorded pose not after it (null before the first).
  const TruthPose* At(TimeNs stamp) const;

  /// TUM trajectory ("t x y z qx qy qz qw"), two comment lines first: `what` and the columns.
  /// `planar`: the planar pose lifted to 3D (what the metrics score), else the full 3D pose.
  std::string Tum(const std::string& what, bool planar) const;

 private:
  void Record(const sim::TruthSample& truth);

  std::set<std::string> frame_cameras_;
  TimeNs period_ns_;
  std::vector<TruthPose> poses_;
  std::vector<SE3> poses_3d_;
  std::vector<FrameTruthSample> frames_;
};

class EventLog : public BusConsumer {
 public:
  void OnEvent(const sim::Event& event) override;
  int count(sim::EventKind kind) const;
  /// events.json: {seed, duration_s, events: [...]} (docs/metrics.md).
  std::string Json(std::uint64_t seed, TimeNs duration_ns) const;

 private:
  nlohmann::ordered_json events_ = nlohmann::ordered_json::array();
  std::vector<sim::EventKind> kinds_;
};

}  // namespace corridorsim
