#pragma once
// `--export` as a bus consumer: the DatasetExporter's calls go to one worker thread in
// submission order (common/io/serial_worker.h), so PNG encoding of exported frames overlaps the
// rendering of the next ones; the files are the bytes inline calls would write. Frame jobs bound
// the queue (four frames), small ones do not.

#include <filesystem>
#include <optional>

#include "common/io/serial_worker.h"
#include "harness/run/export.h"
#include "harness/run/export_imu.h"
#include "harness/run/sensor_bus.h"

namespace corridorsim {

class ExportConsumer : public BusConsumer {
 public:
  /// Opens the export in `dir` for the rendered cameras of `rig` (InputError at `--export` when
  /// the folder cannot take it).
  /// `imus` and `lasers`: the scenario's IMUs and laser scanners, exported as
  /// euroc/mav0/imu<k>/ (with the first IMU's tum_rgbd/accelerometer.txt) and laser<k>/
  /// (harness/run/export_imu.h).
  ExportConsumer(const std::filesystem::path& dir, const render::RigOptions& rig,
                 double wheelbase_m, const std::vector<sim::ImuOptions>& imus = {},
                 const std::vector<sim::LaserOptions>& lasers = {});

  void OnStart(const sim::TruthSample& truth) override;
  void OnOdometry(const WheelOdometry& odometry) override;
  void OnCameraSet(const CameraSet& set) override;
  void OnTruth(const sim::TruthSample& truth) override;
  void OnImu(const sim::ImuMessage& imu) override;
  void OnScan(const sim::ScanMessage& scan) override;

  /// Writes the index files and waits for the worker to finish everything.
  void Finish();
  /// The worker's busy time (overlaps the loop) and the loop's waits on it (a full queue, the
  /// final drain), in wall seconds.
  double busy_seconds() const { return worker_.busy_seconds(); }
  double wait_seconds() const { return wait_seconds_; }

 private:
  std::optional<DatasetExporter> exporter_;
  std::optional<ImuExport> imu_export_;
  std::optional<LaserExport> laser_export_;
  // The first IMU's true biases at its latest sample (b_w, b_a): the ground truth's.
  Eigen::Matrix<double, 6, 1> biases_ = Eigen::Matrix<double, 6, 1>::Zero();
  SerialWorker worker_{4};
  TimeNs truth_period_ns_;
  double wait_seconds_ = 0.0;
};

}  // namespace corridorsim
