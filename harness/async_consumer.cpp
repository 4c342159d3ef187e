#include "harness/async_consumer.h"

#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "harness/stopwatch.h"

namespace corridorsim {

AsyncConsumer::AsyncConsumer(BusConsumer& inner, std::size_t max_frames,
                             std::function<void()> after_step)
    : inner_(inner), after_step_(std::move(after_step)), worker_(max_frames) {}

void AsyncConsumer::Submit(std::function<void()> job, std::size_t weight) {
  const WallClock::time_point t0 = WallClock::now();
  worker_.Submit(std::move(job), weight);
  wait_seconds_ += SecondsSince(t0);
}

void AsyncConsumer::OnStart(const sim::TruthSample& truth) {
  Submit([this, truth] { inner_.OnStart(truth); }, 0);
}

void AsyncConsumer::OnTruth(const sim::TruthSample& truth) {
  Submit([this, truth] { inner_.OnTruth(truth); }, 0);
}

void AsyncConsumer::OnOdometry(const WheelOdometry& odometry) {
  Submit([this, odometry] { inner_.OnOdometry(odometry); }, 0);
}

void AsyncConsumer::OnCameraSet(const CameraSet& set) {
  // The set owns copies of its frames; the slots point into them when the job runs.
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
  Submit(
      [this, owned] {
        for (std::size_t i = 0; i < owned->set.cameras.size(); ++i) {
          owned->set.cameras[i].message = owned->messages[i] ? &*owned->messages[i] : nullptr;
        }
        inner_.OnCameraSet(owned->set);
      },
      1);
}

void AsyncConsumer::OnEvent(const sim::Event& event) {
  Submit([this, event] { inner_.OnEvent(event); }, 0);
}

void AsyncConsumer::OnStepEnd(const sim::TruthSample& truth, bool last) {
  Submit(
      [this, truth, last] {
        inner_.OnStepEnd(truth, last);
        if (after_step_) after_step_();
      },
      0);
}

void AsyncConsumer::Drain() {
  const WallClock::time_point t0 = WallClock::now();
  worker_.Drain();
  wait_seconds_ += SecondsSince(t0);
}

}  // namespace corridorsim
