#pragma once
// Sensor messages as a real robot would hand them to SLAM. They carry no ground truth.

#include <cstdint>
#include <string>

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

}  // namespace corridorsim
