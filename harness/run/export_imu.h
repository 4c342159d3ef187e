#pragma once
// The export's IMUs (docs/export.md): each enabled IMU of the scenario as EuRoC / ASL's
// `euroc/mav0/imu<k>/` (k = 0, 1, ... in the scenario's order): `data.csv` with EuRoC's header
// (`#timestamp [ns],w_RS_S_x [rad s^-1],...,a_RS_S_z [m s^-2]`), one row per sample as the IMU
// reported it, and `sensor.yaml` with T_BS (robot_from_imu), rate_hz and Kalibr's four noise
// figures (what Kalibr, OpenVINS and ORB-SLAM3 read). Rows are written as samples arrive.

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

#include "common/sensor_messages.h"
#include "sim/imu.h"

namespace corridorsim {

class ImuExport {
 public:
  /// Opens `dir`/euroc/mav0/imu<k>/data.csv for each enabled IMU of `imus` (the export's folder,
  /// already checked by DatasetExporter). Throws std::runtime_error naming a file it cannot open.
  ImuExport(const std::filesystem::path& dir, const std::vector<sim::ImuOptions>& imus);
  ~ImuExport();

  /// One sample of enabled IMU `k`; stamps must increase per IMU (std::invalid_argument).
  void Add(std::size_t k, const ImuSample& sample);
  /// Closes the CSVs and writes each sensor.yaml; throws std::runtime_error naming a file that
  /// could not be written whole.
  void Finish();

 private:
  struct Imu;
  std::vector<std::unique_ptr<Imu>> imus_;
};

}  // namespace corridorsim
