#include "harness/run/sensor_bus.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <tuple>
#include <utility>

namespace corridorsim {

const CameraSlot* CameraSet::Find(const std::string& camera_id) const {
  for (const CameraSlot& slot : cameras) {
    if (slot.camera_id == camera_id) return &slot;
  }
  return nullptr;
}

std::vector<CameraSet> GroupCameraSets(const sim::StepOutput& step,
                                       const std::vector<std::string>& camera_ids) {
  // stamp -> camera index -> its frame (null for a dropped one); std::map keeps both in order.
  std::map<TimeNs, std::map<std::size_t, const sim::CameraMessage*>> due;
  for (const sim::CameraMessage& m : step.frames) due[m.stamp_ns][m.camera] = &m;
  for (const sim::Event& e : step.events) {
    if (e.kind != sim::EventKind::kFrameDropped) continue;
    const auto it = std::find(camera_ids.begin(), camera_ids.end(), e.camera_id);
    if (it == camera_ids.end()) continue;  // a camera nobody renders
    due[e.stamp_ns].emplace(static_cast<std::size_t>(it - camera_ids.begin()), nullptr);
  }
  std::vector<CameraSet> sets;
  sets.reserve(due.size());
  for (const auto& [stamp, cameras] : due) {
    CameraSet& set = sets.emplace_back();
    set.stamp_ns = stamp;
    for (const auto& [camera, message] : cameras) {
      set.cameras.push_back({camera_ids.at(camera), camera, message});
    }
  }
  return sets;
}

SensorBus::SensorBus(std::vector<std::string> camera_ids) : camera_ids_(std::move(camera_ids)) {}

void SensorBus::Subscribe(BusConsumer* consumer) { consumers_.push_back(consumer); }

void SensorBus::Publish(const sim::StepOutput& step, bool last) {
  const std::vector<CameraSet> sets = GroupCameraSets(step, camera_ids_);
  // (stamp, kind, index): truth 0, odometry 1, IMU samples 2, laser sweeps 3 (at the stamp of
  // their last beam, when they are complete), camera sets 4, events 5; at one stamp in that
  // order, and within one kind in the order the simulation emitted them. The buffer is reused
  // step to step.
  std::vector<std::tuple<TimeNs, int, std::size_t>>& order = order_;
  order.clear();
  for (std::size_t i = 0; i < step.truth_samples.size(); ++i) {
    order.emplace_back(step.truth_samples[i].stamp_ns, 0, i);
  }
  for (std::size_t i = 0; i < step.odometry.size(); ++i) {
    order.emplace_back(step.odometry[i].stamp_ns, 1, i);
  }
  for (std::size_t i = 0; i < step.imu.size(); ++i)
    order.emplace_back(step.imu[i].sample.stamp_ns, 2, i);
  for (std::size_t i = 0; i < step.scans.size(); ++i) {
    order.emplace_back(step.scans[i].complete_ns, 3, i);
  }
  for (std::size_t i = 0; i < sets.size(); ++i) order.emplace_back(sets[i].stamp_ns, 4, i);
  for (std::size_t i = 0; i < step.events.size(); ++i) {
    order.emplace_back(step.events[i].stamp_ns, 5, i);
  }
  std::sort(order.begin(), order.end());
  for (const auto& [stamp, kind, index] : order) {
    for (BusConsumer* c : consumers_) {
      if (kind == 0) c->OnTruth(step.truth_samples[index]);
      if (kind == 1) c->OnOdometry(step.odometry[index]);
      if (kind == 2) c->OnImu(step.imu[index]);
      if (kind == 3) c->OnScan(step.scans[index]);
      if (kind == 4) c->OnCameraSet(sets[index]);
      if (kind == 5) c->OnEvent(step.events[index]);
    }
  }
  for (BusConsumer* consumer : consumers_) consumer->OnStepEnd(step.truth, last);
}

void SensorBus::Run(sim::Simulation& simulation) {
  using Clock = std::chrono::steady_clock;
  for (BusConsumer* consumer : consumers_) consumer->OnStart(simulation.truth());
  while (!simulation.finished()) {
    const Clock::time_point t0 = Clock::now();
    const sim::StepOutput& step = simulation.Step();
    step_seconds_ += std::chrono::duration<double>(Clock::now() - t0).count();
    Publish(step, simulation.finished());
  }
}

}  // namespace corridorsim
