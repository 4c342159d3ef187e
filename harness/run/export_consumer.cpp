#include "harness/run/export_consumer.h"

#include <stdexcept>

#include "common/error.h"
#include "harness/run/run_io.h"
#include "harness/run/stopwatch.h"

namespace corridorsim {

ExportConsumer::ExportConsumer(const std::filesystem::path& dir, const render::RigOptions& rig,
                               double wheelbase_m, const std::vector<sim::ImuOptions>& imus,
                               const std::vector<sim::LaserOptions>& lasers)
    : truth_period_ns_(PeriodFromRateHz(kTruthFileRateHz)) {
  try {
    exporter_.emplace(dir, rig, wheelbase_m);
    const render::CameraOptions* front = rig.Find("front");
    imu_export_.emplace(dir, imus, front != nullptr && front->enabled);
    laser_export_.emplace(dir, lasers);
  } catch (const std::runtime_error& e) {
    throw InputError(SourceLocation{"command line", 0, 0}, "--export", e.what());
  }
}

void ExportConsumer::OnStart(const sim::TruthSample& truth) {
  const SE3 pose = truth.state.world_from_robot;
  worker_.Submit([this, pose] { exporter_->AddTruth(0, pose); }, 0);
}

void ExportConsumer::OnOdometry(const WheelOdometry& odometry) {
  worker_.Submit([this, odometry] { exporter_->AddOdometry(odometry); }, 0);
}

void ExportConsumer::OnCameraSet(const CameraSet& set) {
  for (const CameraSlot& slot : set.cameras) {
    if (!slot.message) continue;
    const WallClock::time_point t0 = WallClock::now();
    // The job holds a copy of the frame: the message lives only during the delivery.
    worker_.Submit(
        [this, message = *slot.message, id = slot.camera_id] { exporter_->AddFrame(message, id); });
    wait_seconds_ += SecondsSince(t0);
  }
}

void ExportConsumer::OnTruth(const sim::TruthSample& truth) {
  // The grid's points (odometry stamps off the grid are left out), whatever the physics rate.
  if (truth.stamp_ns % truth_period_ns_ != 0) return;
  const TimeNs stamp = truth.stamp_ns;
  const SE3 pose = truth.state.world_from_robot;
  worker_.Submit([this, stamp, pose, b = biases_] { exporter_->AddTruth(stamp, pose, b); }, 0);
}

void ExportConsumer::OnImu(const sim::ImuMessage& imu) {
  if (imu.imu == 0) biases_ << imu.gyroscope_bias, imu.accelerometer_bias;
  worker_.Submit([this, k = imu.imu, sample = imu.sample] { imu_export_->Add(k, sample); }, 0);
}

void ExportConsumer::OnScan(const sim::ScanMessage& scan) {
  worker_.Submit([this, k = scan.laser, sweep = scan.scan] { laser_export_->Add(k, sweep); }, 0);
}

void ExportConsumer::Finish() {
  const WallClock::time_point t0 = WallClock::now();
  worker_.Submit([this] {
    exporter_->Finish();
    imu_export_->Finish(exporter_->has_tum());
    laser_export_->Finish();
  });
  worker_.Drain();
  wait_seconds_ += SecondsSince(t0);
}

}  // namespace corridorsim
