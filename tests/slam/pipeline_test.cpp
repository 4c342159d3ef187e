// Tests slam/pipeline.cpp: what a calibration must hold.
#include "slam/pipeline.h"

#include <catch2/catch.hpp>

#include "tests/support/pioneer_calibration.h"

namespace corridorsim::slam {
namespace {

using test::PioneerCalibration;

TEST_CASE("a calibration names its first missing or impossible value", "[slam]") {
  CHECK_FALSE(PioneerCalibration().Check());
  Calibration calibration = PioneerCalibration();
  calibration.wheelbase_m = 0.0;
  REQUIRE(calibration.Check());
  CHECK(calibration.Check()->key == "wheelbase_m");
  calibration = PioneerCalibration();
  calibration.ticks_per_revolution = -1;
  REQUIRE(calibration.Check());
  CHECK(calibration.Check()->key == "ticks_per_revolution");
  calibration = PioneerCalibration();
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
