#pragma once
// The export's IMUs and laser scanners (docs/export.md), the sensors that need no rendering: each
// enabled IMU of the scenario as EuRoC / ASL's `euroc/mav0/imu<k>/` (k = 0, 1, ... in the
// scenario's order): `data.csv` with EuRoC's header
// (`#timestamp [ns],w_RS_S_x [rad s^-1],...,a_RS_S_z [m s^-2]`), one row per sample as the IMU
// reported it, and `sensor.yaml` with T_BS (robot_from_imu), rate_hz and Kalibr's four noise
// figures (what Kalibr, OpenVINS and ORB-SLAM3 read). Rows are written as samples arrive.
// Beside the front camera's TUM RGB-D sequence, the first IMU's accelerometer as TUM RGB-D's
// `tum_rgbd/accelerometer.txt` (three comment lines, then `timestamp ax ay az`: seconds with nine
// decimals, m/s^2): specific force, gravity included, in the IMU's own frame (its T_BS in
// euroc/mav0/imu0/sensor.yaml), where TUM's came from the Kinect's accelerometer.
// And each enabled laser scanner of the scenario as `euroc/mav0/laser<k>/` (k = 0, 1, ... in the
// scenario's order), in the ASL folder form of the cameras and IMUs: `data.csv` with one row per
// sweep, the fields of ROS's sensor_msgs/LaserScan
// (`#timestamp [ns],angle_min [rad],angle_increment [rad],time_increment [s],range_min [m],
// range_max [m],ranges [m]...`: the stamp of its first beam, then every beam's range with REP
// 117's inf, -inf and nan), and `sensor.yaml` with T_BS (robot_from_laser) and the sweep's fixed
// geometry (export_yaml.h: LaserSensorYaml). Rows are written as the sweeps arrive; a scanner
// that swept nothing writes nothing.

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

#include "common/sensor_messages.h"
#include "sim/imu.h"
#include "sim/laser_scanner.h"

namespace corridorsim {

class ImuExport {
 public:
  /// Opens `dir`/euroc/mav0/imu<k>/data.csv for each enabled IMU of `imus` (the export's folder,
  /// already checked by DatasetExporter), and with `tum` (the front camera is enabled) and an
  /// IMU `dir`/tum_rgbd/accelerometer.txt. Throws std::runtime_error naming a file it cannot open.
  ImuExport(const std::filesystem::path& dir, const std::vector<sim::ImuOptions>& imus, bool tum);
  ~ImuExport();

  /// One sample of enabled IMU `k`; stamps must increase per IMU (std::invalid_argument).
  void Add(std::size_t k, const ImuSample& sample);
  /// Closes the CSVs and writes each sensor.yaml; throws std::runtime_error naming a file that
  /// could not be written whole. `has_tum`: the front camera wrote its sequence; without it the
  /// accelerometer.txt is removed (with tum_rgbd/ when that is then empty).
  void Finish(bool has_tum);

 private:
  struct Imu;
  std::vector<std::unique_ptr<Imu>> imus_;
  std::filesystem::path accelerometer_path_;  // empty: none
  std::ofstream accelerometer_;
};

class LaserExport {
 public:
  /// The enabled scanners of `lasers`, exported under `dir` (the export's folder, already checked
  /// by DatasetExporter).
  LaserExport(const std::filesystem::path& dir, const std::vector<sim::LaserOptions>& lasers);
  ~LaserExport();

  /// One sweep of enabled scanner `k`: the first opens its folder and data.csv (std::runtime_error
  /// naming a file it cannot open). Stamps must increase per scanner and every sweep of a scanner
  /// has its first sweep's beam count (std::invalid_argument).
  void Add(std::size_t k, const LaserScan& scan);
  /// Closes the CSVs and writes each sensor.yaml; throws std::runtime_error naming a file that
  /// could not be written whole.
  void Finish();

 private:
  struct Laser;
  std::vector<std::unique_ptr<Laser>> lasers_;
};

}  // namespace corridorsim
