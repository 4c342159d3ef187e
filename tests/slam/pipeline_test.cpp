// Tests slam/pipeline.cpp: what a calibration must hold, and what a detection must carry.
#include "slam/pipeline.h"

#include <limits>

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
  CHECK(calibration.Check()->message == "must be greater than depth.min_m (got 0.4 <= 0.5)");
  calibration.cameras[0].model = CameraModel();
  REQUIRE(calibration.Check());
  CHECK(calibration.Check()->key == "cameras.front.model");
}

Detection Valid(LandmarkType type) {
  Detection d;
  d.camera_id = "front";
  d.type = type;
  d.pixel = Eigen::Vector2d(10, 20);
  if (type == LandmarkType::kDoorPlate || type == LandmarkType::kDoor) {
    d.box_px = Eigen::Vector4d(5, 15, 15, 25);
  }
  if (type == LandmarkType::kLamp) d.radius_px = 4.0;
  return d;
}

TEST_CASE("a detection is checked for the fields its type needs", "[slam]") {
  for (const LandmarkType type :
       {LandmarkType::kDoorPlate, LandmarkType::kCorner, LandmarkType::kLamp, LandmarkType::kDoor,
        LandmarkType::kVanishingPoint}) {
    CHECK_FALSE(DetectionProblem(Valid(type)));
  }
  Detection plate = Valid(LandmarkType::kDoorPlate);
  plate.box_px = Eigen::Vector4d(15, 15, 5, 25);  // min x > max x
  CHECK(DetectionProblem(plate));
  Detection lamp = Valid(LandmarkType::kLamp);
  lamp.radius_px = 0.0;
  CHECK(DetectionProblem(lamp));
  Detection corner = Valid(LandmarkType::kCorner);
  corner.label = "101";
  CHECK(DetectionProblem(corner));
  corner = Valid(LandmarkType::kCorner);
  corner.pixel.x() = std::numeric_limits<double>::quiet_NaN();
  CHECK(DetectionProblem(corner));
  Detection read = Valid(LandmarkType::kDoorPlate);
  read.recognition_score = 1.5;
  CHECK(DetectionProblem(read));
  read.recognition_score = 0.97;
  CHECK_FALSE(DetectionProblem(read));
  Detection vp = Valid(LandmarkType::kVanishingPoint);
  vp.recognition_score = 0.5;
  CHECK(DetectionProblem(vp));
  Detection no_camera = Valid(LandmarkType::kCorner);
  no_camera.camera_id.clear();
  CHECK(DetectionProblem(no_camera));
  // Column bearings (P3 eq. 17): doors only, both angles.
  Detection door = Valid(LandmarkType::kDoor);
  door.column_bearings_rad = Eigen::Vector2d(0.3, -2.0);
  CHECK_FALSE(DetectionProblem(door));
  door.column_bearings_rad(1) = 4.0;
  CHECK(DetectionProblem(door));
  door.column_bearings_rad(1) = std::numeric_limits<double>::quiet_NaN();
  CHECK(DetectionProblem(door));
  Detection lamp_with_bearings = Valid(LandmarkType::kLamp);
  lamp_with_bearings.column_bearings_rad = Eigen::Vector2d(0.1, 0.2);
  CHECK(DetectionProblem(lamp_with_bearings));
}

TEST_CASE("a pipeline's declaration of its own measurement types is checked", "[slam]") {
  CHECK_FALSE(MeasurementTypesProblem({}));
  CHECK_FALSE(MeasurementTypesProblem({{"scan_match", 3}, {"gyro_bias", 1}}));
  CHECK(IsMeasurementTypeName("wall_line2"));
  for (const char* name : {"", "Scan", "2d", "scan-match", "lamp", "door_plate",
                           "a23456789012345678901234567890123"}) {
    INFO(name);
    CHECK_FALSE(IsMeasurementTypeName(name));
    const std::optional<std::string> problem = MeasurementTypesProblem({{name, 1}});
    REQUIRE(problem);
    CHECK(problem->find("number 1") != std::string::npos);
  }
  CHECK(IsMeasurementTypeName("a2345678901234567890123456789012"));  // 32 bytes
  CHECK(MeasurementTypesProblem({{"wall", 2}, {"wall", 2}}) ==
        std::optional<std::string>("declares the measurement type 'wall' twice"));
  CHECK(MeasurementTypesProblem({{"wall", 0}})->find("0 degrees of freedom") != std::string::npos);
  CHECK(MeasurementTypesProblem({{"wall", kMaxMeasurementDof + 1}}));
  std::vector<MeasurementType> many;
  for (int i = 0; i <= kMaxMeasurementTypes; ++i) many.push_back({"t" + std::to_string(i), 1});
  CHECK(MeasurementTypesProblem(many)->find("at most 32") != std::string::npos);
}

TEST_CASE("a detection or innovation of an own type goes by its name, not its landmark type",
          "[slam]") {
  Detection d;
  d.camera_id = "front";
  d.type = LandmarkType::kLamp;
  CHECK(d.Is(LandmarkType::kLamp));
  CHECK(MeasurementName(d) == "lamp");
  d.measurement = "wall_line";
  CHECK_FALSE(d.Is(LandmarkType::kLamp));
  CHECK(MeasurementName(d) == "wall_line");
  // A lamp's missing radius does not matter to an own type; a shipped type's field does.
  CHECK_FALSE(DetectionProblem(d));
  d.label = "101";
  CHECK(DetectionProblem(d));
  Innovation n;
  n.type = LandmarkType::kDoor;
  CHECK(MeasurementName(n) == "door");
  n.measurement = "scan_match";
  CHECK(MeasurementName(n) == "scan_match");
}

}  // namespace
}  // namespace corridorsim::slam
