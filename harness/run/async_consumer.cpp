#include "harness/run/async_consumer.h"

#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "harness/run/stopwatch.h"

namespace corridorsim {

AsyncConsumer::AsyncConsumer(BusConsumer& inner, std::size_t max_frames,
                             std::function<void()> after_batch)
    : inner_(inner), after_batch_(std::move(after_batch)), worker_(max_frames) {}

void AsyncConsumer::Queue(std::function<void()> call) {
  batch_.push_back(std::move(call));
  if (batch_.size() >= kMaxBatchCalls) Flush(0);
}

void AsyncConsumer::Flush(std::size_t weight) {
  if (batch_.empty()) return;
  const WallClock::time_point t0 = WallClock::now();
  worker_.Submit(
      [this, calls = std::move(batch_)] {
        for (const std::function<void()>& call : calls) call();
        if (after_batch_) after_batch_();
      },
      weight);
  batch_.clear();  // moved from: valid, emptied
  wait_seconds_ += SecondsSince(t0);
}

void AsyncConsumer::OnStart(const sim::TruthSample& truth) {
  Queue([this, truth] { inner_.OnStart(truth); });
}

void AsyncConsumer::OnTruth(const sim::TruthSample& truth) {
  Queue([this, truth] { inner_.OnTruth(truth); });
}

void AsyncConsumer::OnOdometry(const WheelOdometry& odometry) {
  Queue([this, odometry] { inner_.OnOdometry(odometry); });
}

void AsyncConsumer::OnCameraSet(const CameraSet& set) {
  // The set owns copies of its frames; the slots point into them when the call runs.
  struct Owned {
    CameraSet set;
    std::vector<std::optional<sim::CameraMessage>> messages;
  };
  auto owned = std::make_shared<Owned>();
  owned->set = set;
  owned->messages.reserve(set.cameras.size());
  for (const CameraSlot& slot : set.cameras) {
    owned->messages.push_back(slot.message ? std::optional<sim::CameraMessage>(*slot.message)
                                           : std::nullopt);
  }
  Queue([this, owned] {
    for (std::size_t i = 0; i < owned->set.cameras.size(); ++i) {
      owned->set.cameras[i].message = owned->messages[i] ? &*owned->messages[i] : nullptr;
    }
    inner_.OnCameraSet(owned->set);
  });
  Flush(1);  // a frame closes its batch: it weighs on the queue's bound
}

void AsyncConsumer::OnImu(const sim::ImuMessage& imu) {
  Queue([this, imu] { inner_.OnImu(imu); });
}

void AsyncConsumer::OnScan(const sim::ScanMessage& scan) {
  Queue([this, scan] { inner_.OnScan(scan); });
}

void AsyncConsumer::OnEvent(const sim::Event& event) {
  Queue([this, event] { inner_.OnEvent(event); });
}

void AsyncConsumer::OnStepEnd(const sim::TruthSample& truth, bool last) {
  Queue([this, truth, last] { inner_.OnStepEnd(truth, last); });
  if (last) Flush(0);
}

void AsyncConsumer::Drain() {
  Flush(0);
  const WallClock::time_point t0 = WallClock::now();
  worker_.Drain();
  wait_seconds_ += SecondsSince(t0);
}

}  // namespace corridorsim
