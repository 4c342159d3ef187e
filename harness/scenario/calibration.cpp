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
  for (const sim::ImuOptions& o : scenario.imus) {
    if (!o.enabled) continue;
    const double on = o.noise ? 1.0 : 0.0;
    calibration.imus.push_back({o.id, o.mount.RobotFromBody(), o.rate_hz,
                                on * o.gyroscope_noise_density, on * o.gyroscope_random_walk,
                                on * o.accelerometer_noise_density,
                                on * o.accelerometer_random_walk});
  }
  for (const sim::LaserOptions& o : scenario.lasers) {
    if (!o.enabled) continue;
    calibration.lasers.push_back(
        {o.id, o.mount.RobotFromBody(), o.rate_hz, o.BeamCount(), o.noise ? o.range_sigma_m : 0.0});
  }
  return calibration;
}

std::vector<slam::CameraCalibration> CamerasOfRunScenario(const std::string& path) {
  const YamlDocument doc = YamlDocument::Load(path);
  Scenario scenario;  // the defaults: only its rig is read
  scenario.sensors_location = SourceLocation{path, 0, 0};
  YamlMap root(doc, doc.root, "", &scenario.sources);
  if (root.Has("sensors")) {
    scenario.sensors_location = root.LocationOfKey("sensors");
    YamlMap sensors = root.Map("sensors");
    ReadOptions(sensors, ScenarioSensorsTable(), scenario);
  }
  if (const auto problem = scenario.CheckSensors()) {
    throw LocateProblem(scenario, "sensors", *problem);
  }
  return CalibrationOf(scenario).cameras;
}

}  // namespace corridorsim
