#include "harness/scenario/calibration.h"

namespace corridorsim {

slam::Calibration CalibrationOf(const Scenario& scenario) {
  slam::Calibration calibration;
  calibration.wheelbase_m = scenario.robot.wheelbase_m;
  calibration.wheel_diameter_m = scenario.robot.wheel_diameter_m;
  calibration.ticks_per_revolution = scenario.robot.odometry.ticks_per_revolution;
  for (const render::CameraOptions& c : scenario.rig.cameras) {
    if (!c.enabled) continue;
    slam::CameraCalibration camera;
    camera.id = c.id;
    camera.model = c.model;
    camera.robot_from_camera = c.mount.RobotFromCamera();
    if (c.depth) camera.depth = slam::DepthRange{c.depth_noise.min_m, c.depth_noise.max_m};
    calibration.cameras.push_back(camera);
  }
  return calibration;
}

}  // namespace corridorsim
