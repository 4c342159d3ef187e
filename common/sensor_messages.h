#pragma once
// Sensor messages as a real robot would hand them to SLAM. They carry no ground truth.

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/image.h"
#include "common/time.h"

namespace corridorsim {

/// Wheel odometry since the previous message: the control input u = (s_l, s_r) of P1 eq. 13.
struct WheelOdometry {
  TimeNs stamp_ns = 0;            // end of the interval
  TimeNs interval_ns = 0;         // length of the interval covered by the distances
  double left_distance_m = 0.0;   // s_l, signed travelled distance of the left wheel
  double right_distance_m = 0.0;  // s_r, signed travelled distance of the right wheel
  std::int64_t left_ticks = 0;    // encoder ticks of the interval (quantised source of s_l)
  std::int64_t right_ticks = 0;
};

/// A colour image from one camera.
struct StampedImage {
  TimeNs stamp_ns = 0;
  std::string camera_id;  // e.g. "front", "lateral", "upward"
  Image8 image;           // RGB, row 0 on top
};

/// A depth image registered to a colour camera; 0 marks an invalid pixel.
struct StampedDepth {
  TimeNs stamp_ns = 0;
  std::string camera_id;
  ImageF depth_m;  // metric depth along the optical axis (z in the camera frame), metres
};

/// One IMU sample, in the IMU's own frame (its mount: x forward, y left, z up at zero angles),
/// with the axes and units of ROS's sensor_msgs/Imu. The accelerometer measures specific force:
/// the acceleration minus gravity, so an IMU at rest reads +g (the simulation's 9.81 m/s^2) along
/// its up axis.
struct ImuSample {
  TimeNs stamp_ns = 0;
  std::string sensor_id;
  Eigen::Vector3d angular_velocity_rad_s = Eigen::Vector3d::Zero();    // gyroscope
  Eigen::Vector3d linear_acceleration_m_s2 = Eigen::Vector3d::Zero();  // accelerometer
};

/// One sweep of a planar laser scanner, as ROS's sensor_msgs/LaserScan: beam i points at angle
/// angle_min_rad + i * angle_increment_rad about the scanner's z axis (0 along its x axis,
/// counter-clockwise) and is fired at stamp_ns + i * time_increment_ns, from where the scanner is
/// at that instant (the robot moves during a sweep: docs/sensors.md says how to undistort it).
/// Ranges follow REP 117: +inf no return within range_max_m, -inf closer than range_min_m, NaN
/// a return lost (grazing incidence, dropout).
struct LaserScan {
  TimeNs stamp_ns = 0;  // the first beam
  std::string sensor_id;
  double angle_min_rad = 0.0;
  double angle_increment_rad = 0.0;
  TimeNs time_increment_ns = 0;  // between two beams
  TimeNs scan_time_ns = 0;       // between two sweeps
  double range_min_m = 0.0;
  double range_max_m = 0.0;
  std::vector<float> ranges_m;
};

}  // namespace corridorsim
