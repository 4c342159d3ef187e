#pragma once
// A bus consumer run on a thread of its own: every call is copied (frames included: a message
// lives only during its delivery) and replayed on one worker thread in the order the bus made it
// (common/io/serial_worker.h). The consumer sees exactly the calls it would have seen inline, so
// its outputs are the same bytes; the loop meanwhile steps and renders the next frames. Used for
// the pipelines of a run (docs/architecture.md, "The run loop"). Frames bound the queue. The
// small calls (truth, odometry, events, step ends: about a thousand per simulated second) are
// handed over in batches, closed by each camera set or every kMaxBatchCalls calls, so that the
// thread hand-off costs once per batch, not once per physics step.

#include <cstddef>
#include <functional>
#include <vector>

#include "common/io/serial_worker.h"
#include "harness/run/sensor_bus.h"

namespace corridorsim {

class AsyncConsumer : public BusConsumer {
 public:
  /// `inner` must outlive this object and must not be touched by other threads until Drain()
  /// returns. At most `max_frames` camera sets wait in the queue. `after_batch`, if given, runs on
  /// the worker after each batch of calls (e.g. to publish a snapshot of inner's state).
  AsyncConsumer(BusConsumer& inner, std::size_t max_frames, std::function<void()> after_batch = {});
  static constexpr std::size_t kMaxBatchCalls = 256;

  void OnStart(const sim::TruthSample& truth) override;
  void OnTruth(const sim::TruthSample& truth) override;
  void OnOdometry(const WheelOdometry& odometry) override;
  void OnCameraSet(const CameraSet& set) override;
  void OnImu(const sim::ImuMessage& imu) override;
  void OnScan(const sim::ScanMessage& scan) override;
  void OnEvent(const sim::Event& event) override;
  void OnStepEnd(const sim::TruthSample& truth, bool last) override;

  /// Waits until the inner consumer has seen every call; rethrows the first exception it threw.
  void Drain();
  /// Seconds the loop waited on the worker (a full queue, Drain) and the worker's busy seconds.
  double wait_seconds() const { return wait_seconds_; }
  double busy_seconds() const { return worker_.busy_seconds(); }

 private:
  void Queue(std::function<void()> call);
  /// Hands the calls queued so far to the worker as one job of `weight`.
  void Flush(std::size_t weight);

  BusConsumer& inner_;
  std::function<void()> after_batch_;
  std::vector<std::function<void()>> batch_;
  SerialWorker worker_;
  double wait_seconds_ = 0.0;
};

}  // namespace corridorsim
