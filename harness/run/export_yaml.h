#pragma once
// The YAML files of the dataset export (docs/export.md): ORB-SLAM2/3's settings file for the
// front camera (tum_rgbd/orb_slam.yaml) and the EuRoC / Kalibr sensor.yaml every exported camera
// has (euroc/mav0/camN/sensor.yaml, tum_rgbd/sensor.yaml): its intrinsics, its extrinsics T_BS
// (body_from_sensor, body = the robot frame R) and the body's start pose T_WB_start in frame W.

#include <string>
#include <vector>

#include "common/pose.h"
#include "common/sensor_messages.h"
#include "common/time.h"
#include "render/camera_rig.h"
#include "sim/imu.h"
#include "sim/laser_scanner.h"

namespace corridorsim {

/// The body's (robot frame R) first pose in the world frame W: the first pose of the export's
/// ground truth.
struct BodyStart {
  TimeNs stamp_ns = 0;
  SE3 world_from_robot;
};

/// The shortest text that reads back as the same double, always with a decimal point (ORB-SLAM3
/// insists on reals where it reads reals; YAML readers take it as a float).
std::string YamlReal(double value);

/// `[a, b, ...]` of YamlReal values.
std::string YamlRealList(const std::vector<double>& values);

/// `name:` as EuRoC writes a 4x4 matrix (T_BS, T_WB_start): cols, rows, data row-major.
std::string Matrix4Yaml(const std::string& name, const SE3& pose);

/// ORB-SLAM2's Examples/RGB-D/TUM1.yaml keys for `options` (with ORB-SLAM3's pre-1.0
/// Camera.type, Camera.width and Camera.height); `%YAML:1.0`, read by cv::FileStorage.
std::string OrbSlamYaml(const render::CameraOptions& options);

/// EuRoC's camera sensor.yaml for `options` (plain YAML, as EuRoC's, Kalibr's and TUM-VI's):
/// sensor_type, `comment`, T_BS = the mount's robot_from_camera (4x4, row-major), rate_hz,
/// resolution, camera_model, intrinsics, distortion_model and distortion_coefficients; then
/// T_WB_start (the same 4x4 form: world_from_robot of `start`) and start_timestamp_ns.
std::string CameraSensorYaml(const render::CameraOptions& options, const std::string& comment,
                             const BodyStart& start);

/// An IMU's calibration file, read by EuRoC's, Kalibr's and OpenVINS' YAML readers alike:
/// `sensor_type: imu`, T_BS (robot_from_imu), EuRoC's `rate_hz`, Kalibr's imu.yaml keys
/// (`accelerometer_noise_density`, `accelerometer_random_walk`, `gyroscope_noise_density`,
/// `gyroscope_random_walk`, `rostopic`, `update_rate`); the noise figures are 0 when the
/// scenario turns the IMU's noise off (its samples are then exact).
std::string ImuSensorYaml(const sim::ImuOptions& imu);

/// A laser scanner's geometry: `sensor_type: laser`, T_BS (robot_from_laser) and the fields of
/// ROS's sensor_msgs/LaserScan that do not change from sweep to sweep, as `sweep` (any of its
/// sweeps) has them (angle_min, angle_max, angle_increment in rad, time_increment and scan_time
/// in s, range_min and range_max in m), the beams and the range noise's sigma.
std::string LaserSensorYaml(const sim::LaserOptions& laser, const LaserScan& sweep);

}  // namespace corridorsim
