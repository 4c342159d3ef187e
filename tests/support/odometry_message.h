// A wheel odometry message as the pipeline tests feed it: a stamp and the two wheels' distances
// (no interval, no ticks).
#pragma once

#include "common/sensor_messages.h"

namespace corridorsim::test {

inline WheelOdometry OdometryMessage(TimeNs stamp_ns, double left_m, double right_m) {
  WheelOdometry m;
  m.stamp_ns = stamp_ns;
  m.left_distance_m = left_m;
  m.right_distance_m = right_m;
  return m;
}

}  // namespace corridorsim::test
