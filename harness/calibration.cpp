#include "harness/calibration.h"

namespace corridorsim {

slam::Calibration CalibrationOf(const Scenario& scenario) {
  slam::Calibration calibration;
  calibration.wheelbase_m = scenario.robot.wheelbase_m;
  calibration.wheel_diameter_m = scenario.robot.wheel_diameter_m;
  for (const render::CameraOptions& c : scenario.rig.cameras) {
    if (!c.enabled) continue;
    calibration.cameras.push_back({c.id, c.model, c.mount.RobotFromCamera(), c.depth});
  }
  return calibration;
}

}  // namespace corridorsim
