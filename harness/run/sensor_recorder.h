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

namespace corridorsim {

class SensorRecorder : public BusConsumer {
 public:
  /// `imu_ids` and `laser_ids`: the enabled sensors in the simulation's order
  /// (sim::ImuMessage::imu and sim::ScanMessage::laser index them). With any, the files are
  /// opened in `folder`/sensors/ (the job's staging folder, committed whole) and written row by
  /// row as the messages arrive, so a long run holds none of them in memory:
  /// `<imu>_imu.csv`, `<laser>_scans.csv`, `<laser>_scans_truth.csv`, `<laser>_scans_hits.csv`.
  SensorRecorder(std::vector<std::string> imu_ids, std::vector<std::string> laser_ids,
                 const std::filesystem::path& folder);
  ~SensorRecorder() override;

  void OnImu(const sim::ImuMessage& imu) override;
  void OnScan(const sim::ScanMessage& scan) override;

  /// Closes the files; throws std::runtime_error naming a file that could not be written whole.
  void Finish();
  bool empty() const { return imu_ids_.empty() && laser_ids_.empty(); }

 private:
  struct File {
    std::filesystem::path path;
    std::ofstream out;
  };
  File& Open(const std::string& name);

  std::vector<std::string> imu_ids_, laser_ids_;
  std::filesystem::path dir_;
  std::vector<std::unique_ptr<File>> imu_;                   // per IMU
  std::vector<std::unique_ptr<File>> scans_, truth_, hits_;  // per scanner
};

/// The ids of the enabled sensors of `options` (their `enabled` keys), in order.
template <class Options>
std::vector<std::string> EnabledSensorIds(const std::vector<Options>& options) {
  std::vector<std::string> ids;
  for (const Options& o : options) {
    if (o.enabled) ids.push_back(o.id);
  }
  return ids;
}

}  // namespace corridorsim
