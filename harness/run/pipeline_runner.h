#pragma once
// The pipelines of a run as one bus consumer: every enabled pipeline of the scenario, created
// with the robot's nominal calibration, receives the same sensor stream (so their comparison is
// paired); its estimate is recorded at every odometry message, its detections at every frame,
// and Finish() collects its map, innovations and health for the metrics. A pipeline that throws
// from any call (a plugin's bug, docs/plugins.md) fails alone: its record keeps the reason, it is
// called no more, and the others go on.

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "harness/metrics/metrics.h"
#include "harness/run/sensor_bus.h"
#include "harness/run/truth_recorder.h"
#include "harness/scenario/scenario.h"
#include "slam/pipeline.h"

namespace corridorsim {
namespace external {
class ExternalPipeline;
}

class PipelineRunner : public BusConsumer {
 public:
  /// Creates the scenario's enabled pipelines, each seeded from the run's `seed` (the scenario's,
  /// or --seed's) and its own name. A pipeline that reads a camera the calibration does not have
  /// is an InputError at `pipelines:`.
  PipelineRunner(const Scenario& scenario, const slam::Calibration& calibration,
                 std::uint64_t seed);
  ~PipelineRunner() override;

  /// The cameras any pipeline reads.
  const std::set<std::string>& cameras_used() const { return cameras_used_; }
  std::size_t size() const { return records_.size(); }
  /// "name, name, ..." in scenario order.
  std::string Names() const;

  /// Starts every estimate at the known start pose (P1's runs share it).
  void Initialize(TimeNs stamp_ns, const SE2& world_from_robot);

  void OnOdometry(const WheelOdometry& odometry) override;
  void OnCameraSet(const CameraSet& set) override;
  /// Every IMU sample and laser sweep to every pipeline (slam::Pipeline::OnImu, OnScan).
  void OnImu(const sim::ImuMessage& imu) override;
  void OnScan(const sim::ScanMessage& scan) override;

  /// Ends the run: every pipeline's Finish(), then final landmarks, late detections, innovations,
  /// stage times and health go into the records.
  void Finish();
  /// The pipelines that failed (a call threw), scenario order.
  std::vector<const PipelineRecord*> Failed() const;
  /// One record per pipeline, scenario order.
  const std::vector<PipelineRecord>& records() const { return records_; }
  /// Each pipeline's latest estimate (for a progress line read on another thread), or why it
  /// failed.
  struct Latest {
    std::string name;
    TimeNs stamp_ns = 0;
    Eigen::Vector2d position = Eigen::Vector2d::Zero();
    std::string failed;  // a failed pipeline's reason (its start: kLiveReasonBytes and "...")
  };
  /// Bytes of a failure's reason the live line shows (the whole reason is printed at the end).
  static constexpr std::size_t kLiveReasonBytes = 120;
  std::vector<Latest> LatestEstimates() const;
  /// Each pipeline's current position error against `truth`: "name 0.123 m  ...", and for a
  /// failed one "name failed: <reason>".
  static std::string ErrorsLine(const std::vector<Latest>& latest, const TruthRecorder& truth);
  /// Writes each pipeline's maps (Pipeline::TakeMaps) as `dir/<pipeline><suffix>`, each file
  /// atomically; prints where. Call once, after Finish() and the metrics (the maps are moved
  /// out, and the records' occupancy maps are no longer valid).
  void WriteMaps(const std::filesystem::path& dir);
  /// Wall seconds spent inside the pipelines (frames run the pipelines that read them
  /// concurrently, so this is less than the sum of their own times).
  double seconds() const;

 private:
  struct Run;
  // Calls `call` on run i unless it failed before; an exception makes it fail (named `what` at
  // `stamp_ns`). Returns whether the call returned normally.
  template <class F>
  bool Guard(std::size_t i, const char* what, TimeNs stamp_ns, F&& call);
  // Guard(i, ...) for every pipeline, its time added to its cost.
  template <class F>
  void Timed(const char* what, TimeNs stamp_ns, F&& call);
  // What a failed program's replies brought before (and with) the mistake, into its record.
  static void KeepWhatArrived(external::ExternalPipeline& program, PipelineRecord& record);
  // The camera set to the pipelines that take sets whole (programs, harness/external).
  void OnCameraSetWhole(const CameraSet& set);
  // Run i's detections of the frames of `set`, checked (a bad one fails the pipeline), into its
  // record.
  void TakeDetections(std::size_t i, const CameraSet& set, TimeNs stamp_ns);
  // Run i's innovations since the last call, checked against its declared measurement types (an
  // undeclared type or a wrong dof fails the pipeline at once), into its record.
  void TakeInnovations(std::size_t i, TimeNs stamp_ns);
  // What is wrong with a detection (dof: nothing) or an innovation of `measurement` from run i,
  // or nothing: a type it did not declare, or a dof other than the declared one.
  std::optional<std::string> MeasurementProblem(std::size_t i, const std::string& measurement,
                                                std::optional<int> dof) const;
  std::vector<Run> runs_;
  std::vector<PipelineRecord> records_;
  std::set<std::string> cameras_used_;
  std::map<std::string, CameraModel> true_models_;
  double wall_seconds_ = 0.0;  // the rig's cameras (truth, not calibration)
  TimeNs last_stamp_ns_ = 0;   // of the last message handed to the pipelines
};

}  // namespace corridorsim
