#pragma once
// Bus consumers that keep what the metrics and the run folder need of the ground truth: the
// robot's pose on the 100 Hz grid and at every odometry stamp, whatever the physics rate
// (TruthRecorder, with the camera frames' truth for detector scores), and the simulation's
// events (EventLog, events.json).

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/pose.h"
#include "harness/metrics/metrics.h"
#include "harness/run/sensor_bus.h"

namespace corridorsim {

class TruthRecorder : public BusConsumer {
 public:
  /// Keeps the truth of the frames of `frame_cameras` (the cameras some pipeline reads).
  explicit TruthRecorder(std::set<std::string> frame_cameras = {});

  void OnStart(const sim::TruthSample& truth) override;
  void OnTruth(const sim::TruthSample& truth) override;
  void OnCameraSet(const CameraSet& set) override;

  /// Planar truth at 0, every truth-grid point (kTruthFileRateHz) and every odometry stamp, in
  /// stamp order, each stamp once, whatever the physics rate: every estimate (stamped by its
  /// odometry message) has its exact truth here, and a run of a given duration has the same rows
  /// at any physics rate.
  const std::vector<TruthPose>& poses() const { return poses_; }
  const std::vector<FrameTruthSample>& frames() const { return frames_; }
  /// The truth at `stamp`: the last recorded pose not after it (null before the first).
  const TruthPose* At(TimeNs stamp) const;

  /// ground_truth.tum of `drive` and `run` alike: poses() as TUM lines ("t x y z qx qy qz qw"),
  /// the planar pose lifted to 3D (z = 0, no roll or pitch): what the metrics score.
  std::string PlanarTum() const;
  /// ground_truth_3d.tum of `drive`: the full 3D pose of the physics (the chassis' height,
  /// roll and pitch included) at the same stamps.
  std::string FullPoseTum() const;

 private:
  void Record(const sim::TruthSample& truth);

  std::set<std::string> frame_cameras_;
  std::vector<TruthPose> poses_;
  std::vector<SE3> poses_3d_;
  std::vector<FrameTruthSample> frames_;
};

class EventLog : public BusConsumer {
 public:
  void OnEvent(const sim::Event& event) override;
  /// A pipeline that failed (harness/run/pipeline_runner.h): an event `pipeline_failed` with the
  /// pipeline, the call that threw and its text, placed among the simulation's events by its
  /// stamp (after those of the same stamp), whenever it is added.
  void AddPipelineFailure(TimeNs stamp_ns, const std::string& pipeline, const std::string& call,
                          const std::string& what);
  int count(sim::EventKind kind) const;
  /// events.json: {seed, duration_s, events: [...]} (docs/metrics.md).
  std::string Json(std::uint64_t seed, TimeNs duration_ns) const;

 private:
  nlohmann::ordered_json events_ = nlohmann::ordered_json::array();
  std::vector<sim::EventKind> kinds_;
  std::vector<std::pair<TimeNs, nlohmann::ordered_json>> failures_;  // in the order added
};

}  // namespace corridorsim
