// Tests harness/scenario/calibration.cpp: the calibration a pipeline gets is the scenario's nominal
// robot, encoders and enabled cameras.
#include "harness/scenario/calibration.h"

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

TEST_CASE("the calibration holds the scenario's nominal robot, encoders and cameras", "[harness]") {
  Scenario scenario;
  scenario.robot.wheelbase_m = 0.4;
  scenario.robot.wheel_diameter_m = 0.2;
  scenario.robot.odometry.ticks_per_revolution = 1000;
  scenario.robot.odometry.wheelbase_ratio = 1.01;  // the real robot's, not the calibration's
  scenario.rig.cameras[0].depth_noise.min_m = 0.6;
  scenario.rig.cameras[0].depth_noise.max_m = 6.0;
  scenario.rig.cameras[1].enabled = false;
  const slam::Calibration calibration = CalibrationOf(scenario);
  CHECK_FALSE(calibration.Check());
  CHECK(calibration.wheelbase_m == 0.4);
  CHECK(calibration.wheel_diameter_m == 0.2);
  CHECK(calibration.ticks_per_revolution == 1000);
  REQUIRE(calibration.cameras.size() == 2);
  CHECK(calibration.Find("lateral") == nullptr);
  const slam::CameraCalibration& front = *calibration.Find("front");
  const render::CameraOptions& front_options = scenario.rig.cameras[0];
  CHECK(front.model == front_options.model);
  CHECK(front.robot_from_camera.translation() ==
        front_options.mount.RobotFromCamera().translation());
  CHECK(front.robot_from_camera.rotation() == front_options.mount.RobotFromCamera().rotation());
  REQUIRE(front.depth.has_value());
  CHECK(front.depth->min_m == 0.6);
  CHECK(front.depth->max_m == 6.0);
  const slam::CameraCalibration& upward = *calibration.Find("upward");
  CHECK(upward.model == scenario.rig.cameras[2].model);
  CHECK_FALSE(upward.depth.has_value());
}

TEST_CASE("the default scenario's calibration is the Pioneer 3-DX's", "[harness]") {
  const Scenario scenario;
  const slam::Calibration calibration = CalibrationOf(scenario);
  CHECK_FALSE(calibration.Check());
  CHECK(calibration.wheelbase_m == sim::RobotOptions{}.wheelbase_m);
  CHECK(calibration.wheel_diameter_m == sim::RobotOptions{}.wheel_diameter_m);
  CHECK(calibration.ticks_per_revolution == sim::OdometryOptions{}.ticks_per_revolution);
  CHECK(calibration.cameras.size() == scenario.rig.cameras.size());
}

TEST_CASE("the encoder resolution has one upper bound in the scenario and the calibration",
          "[harness]") {
  Scenario scenario;
  scenario.robot.odometry.ticks_per_revolution = kMaxTicksPerRevolution;
  CHECK_FALSE(scenario.robot.odometry.Check());
  CHECK_FALSE(CalibrationOf(scenario).Check());
  scenario.robot.odometry.ticks_per_revolution = kMaxTicksPerRevolution + 1;
  const std::optional<OptionsProblem> options = scenario.robot.odometry.Check();
  REQUIRE(options);
  CHECK(options->key == "ticks_per_revolution");
  CHECK_THAT(options->message, Catch::Contains("got 1000001)"));
  const std::optional<OptionsProblem> calibration = CalibrationOf(scenario).Check();
  REQUIRE(calibration);
  CHECK(calibration->key == "ticks_per_revolution");
  CHECK_THAT(calibration->message, Catch::Contains("got 1000001)"));
}

}  // namespace
}  // namespace corridorsim
