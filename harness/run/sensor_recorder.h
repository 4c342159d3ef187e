#pragma once
// The run folder's files of the sensors that need no rendering (docs/sensors.md, "In the run
// folder"): each IMU's samples with their truth, each laser scanner's sweeps with their truth.
// `run` and `drive` subscribe one to the bus when the scenario has such sensors.

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "harness/run/sensor_bus.h"
#include "sim/imu.h"
#include "sim/laser_scanner.h"

namespace corridorsim {

class SensorRecorder : public BusConsumer {
 public:
  /// The enabled sensors of `imus` and `lasers`, in the simulation's order
  /// (sim::ImuMessage::imu and sim::ScanMessage::laser index them). With any, the files are
  /// opened in `folder`/sensors/ (the job's staging folder, committed whole) and written row by
  /// row as the messages arrive, so a long run holds none of them in memory:
  /// `<imu>_imu.csv`, `<laser>_scans.csv`, `<laser>_scans_truth.csv`, `<laser>_scans_hits.csv`,
  /// and each sensor's calibration file (harness/run/export_yaml.h): `<imu>_imu.yaml` (Kalibr's
  /// imu.yaml keys, EuRoC's sensor.yaml), `<laser>_laser.yaml` (its geometry, at its first sweep).
  SensorRecorder(const std::vector<sim::ImuOptions>& imus,
                 const std::vector<sim::LaserOptions>& lasers, const std::filesystem::path& folder);
  ~SensorRecorder() override;

  void OnImu(const sim::ImuMessage& imu) override;
  void OnScan(const sim::ScanMessage& scan) override;

  /// Closes the files; throws std::runtime_error naming a file that could not be written whole.
  void Finish();
  bool empty() const { return imu_.empty() && lasers_.empty(); }

 private:
  struct File {
    std::filesystem::path path;
    std::ofstream out;
  };
  // A new file `name` in sensors/, appended to `into`.
  File& Open(std::vector<std::unique_ptr<File>>& into, const std::string& name);

  std::vector<sim::LaserOptions> lasers_;
  std::filesystem::path dir_;
  std::vector<std::unique_ptr<File>> imu_;                   // per IMU
  std::vector<std::unique_ptr<File>> scans_, truth_, hits_;  // per scanner
};

}  // namespace corridorsim
