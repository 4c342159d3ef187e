// The calibration of a Pioneer 3-DX-like robot, without cameras, for tests of the pipelines that
// read a slam::Calibration.
#pragma once

#include "slam/pipeline.h"

namespace corridorsim::test {

inline slam::Calibration PioneerCalibration() {
  return slam::Calibration{
      .wheelbase_m = 0.33, .wheel_diameter_m = 0.195, .ticks_per_revolution = 39400, .cameras = {}};
}

}  // namespace corridorsim::test
