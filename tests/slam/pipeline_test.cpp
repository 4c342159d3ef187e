// Tests slam/pipeline.cpp: what a calibration must hold.
#include "slam/pipeline.h"

#include <catch2/catch.hpp>

namespace corridorsim::slam {
namespace {

// A Pioneer 3-DX-like robot's calibration, without cameras.
Calibration Robot() {
  Calibration calibration;
  calibration.wheelbase_m = 0.33;
  calibration.wheel_diameter_m = 0.195;
  calibration.ticks_per_revolution = 39400;
  return calibration;
}

TEST_CASE("a calibration names its first missing or impossible value", "[slam]") {
  CHECK_FALSE(Robot().Check());
  Calibration calibration = Robot();
  calibration.wheelbase_m = 0.0;
  REQUIRE(calibration.Check());
  CHECK(calibration.Check()->key == "wheelbase_m");
  calibration = Robot();
  calibration.ticks_per_revolution = -1;
  REQUIRE(calibration.Check());
  CHECK(calibration.Check()->key == "ticks_per_revolution");
  calibration = Robot();
  CameraCalibration camera;
  camera.id = "front";
  camera.model = PinholeRadTan::FromFov(640, 480, 1.0);
  camera.depth = DepthRange{0.5, 8.0};
  calibration.cameras.push_back(camera);
  CHECK_FALSE(calibration.Check());
  REQUIRE(calibration.Find("front") != nullptr);
  calibration.cameras[0].depth = DepthRange{0.5, 0.4};
  REQUIRE(calibration.Check());
  CHECK(calibration.Check()->key == "cameras.front.depth.max_m");
  calibration.cameras[0].model = CameraModel();
  REQUIRE(calibration.Check());
  CHECK(calibration.Check()->key == "cameras.front.model");
}

}  // namespace
}  // namespace corridorsim::slam
