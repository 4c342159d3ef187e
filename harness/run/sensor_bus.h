#pragma once
// The run loop's one time-ordered sensor bus (docs/architecture.md, "How a run is made"): the
// simulation publishes what became due in each physics step and the consumers that subscribed
// (pipelines, the truth recorder, the exporter, the frame writer, the progress line) receive it
// in stamp order. No consumer drives the loop; `drive`, `run` and `study` only choose which
// consumers listen (Cartographer's sensor::Collator is the model).
//
// Within a step, messages are delivered in stamp order; at one stamp the truth comes first
// (on the truth grid and at odometry stamps, whatever the physics rate), then odometry, then IMU
// samples, then laser sweeps (at their last beam's stamp), then the camera set, then events. After
// the step's messages every consumer sees the truth at the step's end. Frames of several cameras
// due at one stamp arrive as one CameraSet, so a pipeline that fuses cameras sees them together; a
// frame that was due but dropped
// (`sensors.<camera>.drop_probability`) leaves its slot in the set with no message.

#include <cstddef>
#include <string>
#include <tuple>
#include <vector>

#include "common/sensor_messages.h"
#include "common/time.h"
#include "sim/simulation.h"

namespace corridorsim {

/// One camera of a set: its frame, or none when the frame due at the set's stamp was dropped.
struct CameraSlot {
  std::string camera_id;
  std::size_t camera = 0;                       // index in the rig's rendered cameras
  const sim::CameraMessage* message = nullptr;  // null: dropped; valid during the delivery only
};

/// The frames of the rendered cameras due at one stamp, in the rig's camera order. Cameras that
/// were not due at the stamp (another rate or phase) have no slot.
struct CameraSet {
  TimeNs stamp_ns = 0;
  std::vector<CameraSlot> cameras;

  /// The slot of `camera_id`, or null when that camera was not due at this stamp.
  const CameraSlot* Find(const std::string& camera_id) const;
};

/// A subscriber of the bus. Every hook defaults to doing nothing.
class BusConsumer {
 public:
  virtual ~BusConsumer() = default;
  /// The truth before the first step (stamp 0).
  virtual void OnStart(const sim::TruthSample& truth) { (void)truth; }
  /// The truth at a truth-grid or odometry stamp inside a step (sim::StepOutput::truth_samples),
  /// before the messages of that stamp. Never stamp 0 (OnStart has it).
  virtual void OnTruth(const sim::TruthSample& truth) { (void)truth; }
  // Sensor messages: what a real robot would receive.
  virtual void OnOdometry(const WheelOdometry& odometry) { (void)odometry; }
  virtual void OnCameraSet(const CameraSet& set) { (void)set; }
  /// An IMU sample (what the IMU reports, with its truth), and a laser sweep once its last beam
  /// has fired (sim/motion_sensors.h).
  virtual void OnImu(const sim::ImuMessage& imu) { (void)imu; }
  virtual void OnScan(const sim::ScanMessage& scan) { (void)scan; }
  // Simulation events (collisions, slips, dropped frames, path done, timeout): ground truth.
  virtual void OnEvent(const sim::Event& event) { (void)event; }
  /// The truth at the end of a step, after the step's messages; `last`: the run is over.
  virtual void OnStepEnd(const sim::TruthSample& truth, bool last) {
    (void)truth;
    (void)last;
  }
};

class SensorBus {
 public:
  /// `camera_ids`: the ids of the rendered cameras in the rig's order (CameraMessage::camera
  /// indexes them).
  explicit SensorBus(std::vector<std::string> camera_ids);

  /// Consumers receive each message in the order they subscribed. They must outlive the bus's
  /// deliveries.
  void Subscribe(BusConsumer* consumer);

  /// Announces the start truth, then steps `simulation` until it is finished, publishing every
  /// step.
  void Run(sim::Simulation& simulation);

  /// Delivers one step's output (Run's body; tests call it directly).
  void Publish(const sim::StepOutput& step, bool last);

  /// The consumers in subscription order (replay delivers a recorded stream to them directly:
  /// harness/record/replay_source.h).
  const std::vector<BusConsumer*>& consumers() const { return consumers_; }

  /// Wall-clock seconds spent inside Simulation::Step (physics and rendering) during Run.
  double step_seconds() const { return step_seconds_; }

 private:
  std::vector<std::string> camera_ids_;
  std::vector<BusConsumer*> consumers_;
  std::vector<std::tuple<TimeNs, int, std::size_t>> order_;  // (stamp, kind, index) of a step
  double step_seconds_ = 0.0;
};

/// The camera sets of one step's frames and dropped-frame events, in stamp order.
std::vector<CameraSet> GroupCameraSets(const sim::StepOutput& step,
                                       const std::vector<std::string>& camera_ids);

}  // namespace corridorsim
