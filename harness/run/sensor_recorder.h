#pragma once
// The run folder's files of the sensors that need no rendering (docs/sensors.md, "In the run
// folder"): each IMU's samples with their truth, each laser scanner's sweeps with their truth.
// `run` and `drive` subscribe one to the bus when the scenario has such sensors.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "harness/run/sensor_bus.h"

namespace corridorsim {

class SensorRecorder : public BusConsumer {
 public:
  /// `imu_ids` and `laser_ids`: the enabled sensors in the simulation's order
  /// (sim::ImuMessage::imu and sim::ScanMessage::laser index them).
  SensorRecorder(std::vector<std::string> imu_ids, std::vector<std::string> laser_ids);

  void OnImu(const sim::ImuMessage& imu) override;
  void OnScan(const sim::ScanMessage& scan) override;

  /// Writes `sensors/<imu>_imu.csv`, `sensors/<laser>_scans.csv`, `<laser>_scans_truth.csv` and
  /// `<laser>_scans_hits.csv` into `folder` (atomically, file by file); nothing without sensors.
  void Write(const std::filesystem::path& folder) const;
  bool empty() const { return imu_ids_.empty() && laser_ids_.empty(); }

 private:
  std::vector<std::string> imu_ids_, laser_ids_;
  std::vector<std::string> imu_csv_;                           // per IMU
  std::vector<std::string> scans_csv_, truth_csv_, hits_csv_;  // per scanner
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
