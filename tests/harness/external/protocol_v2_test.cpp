// Tests protocol version 2 (harness/external/protocol.h, docs/protocol.md "Version 2"): what
// start offers, the ready reply's negotiation (version, sensors, measurement types), the imu and
// scan messages (REP 117's non-finite ranges as IEEE float32 bits in the blob), and innovations
// and detections of a declared measurement type.
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <catch2/catch.hpp>

#include "harness/external/protocol.h"

namespace corridorsim::external {
namespace {

using Catch::Matchers::Contains;

nlohmann::json Json(const char* text) { return nlohmann::json::parse(text); }

slam::Calibration RobotWithSensors() {
  slam::Calibration c{0.381, 0.195, 0, {}, {}, {}};
  c.imus.push_back({"imu0", SE3(), 1000.0, 1.7e-4, 1.9e-5, 2e-3, 3e-3});
  c.imus.push_back({"imu1", SE3(), 200.0, 0, 0, 0, 0});
  c.lasers.push_back({"scanner", SE3(), 37.5, 361, 0.01});
  return c;
}

TEST_CASE("start offers version 2 and the IMUs' and scanners' calibration",
          "[external][protocol]") {
  const nlohmann::ordered_json start = StartMessage("mine", RobotWithSensors(), {}, 0, SE2(0, 0, 0),
                                                    nlohmann::ordered_json::object(), 7, 0);
  CHECK(start["protocol"] == 1);  // what a version-1 client checks
  CHECK(start["protocol_max"] == 2);
  const auto& imus = start["calibration"]["imus"];
  REQUIRE(imus.size() == 2);
  CHECK(imus[0]["id"] == "imu0");
  CHECK(imus[0]["rate_hz"] == 1000.0);
  CHECK(imus[0]["gyroscope_noise_density"] == 1.7e-4);
  CHECK(imus[0]["robot_from_imu"]["rotation"].size() == 9);
  CHECK(start["calibration"]["lasers"][0]["beams"] == 361);
}

TEST_CASE("a ready reply without protocol 2 is version 1 and may not ask for version 2's",
          "[external][protocol]") {
  const OfferedSensors offered = Offered(RobotWithSensors());
  CHECK(ParseReady(Json(R"({"type": "ready"})"), nullptr, offered).protocol == 1);
  CHECK(ParseReady(Json(R"({"type": "ready", "protocol": 1})"), nullptr, offered).protocol == 1);
  CHECK_THROWS_WITH(ParseReady(Json(R"({"type": "ready", "imus": ["imu0"]})"), nullptr, offered),
                    Contains("'imus' is a key of protocol version 2"));
  CHECK_THROWS_WITH(ParseReady(Json(R"({"type": "ready", "protocol": 3})"), nullptr, offered),
                    Contains("ready.protocol: must lie in [1, 2]"));
}

TEST_CASE("a version-2 ready reply names the sensors it reads and its measurement types",
          "[external][protocol]") {
  const OfferedSensors offered = Offered(RobotWithSensors());
  const Ready ready = ParseReady(Json(R"({"type": "ready", "protocol": 2, "imus": ["imu1"],
      "lasers": ["scanner"], "measurement_types": [{"name": "scan_match", "dof": 3}]})"),
                                 nullptr, offered);
  CHECK(ready.protocol == 2);
  CHECK(ready.imus == std::vector<std::string>{"imu1"});
  CHECK(ready.lasers == std::vector<std::string>{"scanner"});
  REQUIRE(ready.measurement_types.size() == 1);
  CHECK(ready.measurement_types[0].name == "scan_match");
  CHECK(ready.measurement_types[0].dof == 3);
  CHECK_THROWS_WITH(
      ParseReady(Json(R"({"type": "ready", "protocol": 2, "imus": ["imu9"]})"), nullptr, offered),
      Contains("ready.imus[0]: 'imu9' is not one of the robot's (imu0, imu1)"));
  CHECK_THROWS_WITH(ParseReady(Json(R"({"type": "ready", "protocol": 2,
                                        "lasers": ["scanner", "scanner"]})"),
                               nullptr, offered),
                    Contains("'scanner' twice"));
  // The checks of slam::MeasurementTypesProblem: a shipped type's name, a dof out of range.
  CHECK_THROWS_WITH(ParseReady(Json(R"({"type": "ready", "protocol": 2,
                                        "measurement_types": [{"name": "lamp", "dof": 2}]})"),
                               nullptr, offered),
                    Contains("ready.measurement_types: the program declares"));
  CHECK_THROWS_WITH(ParseReady(Json(R"({"type": "ready", "protocol": 2,
                                        "measurement_types": [{"name": "wall", "dof": 65}]})"),
                               nullptr, offered),
                    Contains("65 degrees of freedom"));
}

TEST_CASE("innovations and detections of a declared type carry its name; others fail naming it",
          "[external][protocol]") {
  const std::vector<slam::MeasurementType> declared = {{"scan_match", 3}};
  ReplyExtras extras;
  ParseProcessed(Json(R"({"type": "processed", "stamp_ns": 50, "innovations": [
      {"type": "scan_match", "nis": 1.5, "dof": 3}, {"type": "lamp", "nis": 0.5, "dof": 2}],
      "detections": [{"camera": "upward", "type": "scan_match", "pixel": [3, 4], "score": 0.9}]})"),
                 50, {"upward"}, &extras, nullptr, declared);
  REQUIRE(extras.innovations.size() == 2);
  CHECK(extras.innovations[0].measurement == "scan_match");
  CHECK(extras.innovations[0].stamp_ns == 50);
  CHECK(extras.innovations[1].measurement.empty());
  CHECK(extras.innovations[1].type == slam::LandmarkType::kLamp);
  REQUIRE(extras.detections.size() == 1);
  CHECK(extras.detections[0].measurement == "scan_match");
  ReplyExtras more;
  CHECK_THROWS_WITH(ParseProcessed(Json(R"({"type": "processed", "stamp_ns": 50, "innovations": [
                                       {"type": "wall_line", "nis": 1, "dof": 2}]})"),
                                   50, {}, &more, nullptr, declared),
                    Contains("unknown type 'wall_line'") && Contains("scan_match (3 dof)"));
  CHECK_THROWS_WITH(ParseProcessed(Json(R"({"type": "processed", "stamp_ns": 50, "innovations": [
                                       {"type": "scan_match", "nis": 1, "dof": 2}]})"),
                                   50, {}, &more, nullptr, declared),
                    Contains("declared with 3"));
  // Without a declaration the name is unknown (a version-1 program's replies read as before).
  CHECK_THROWS_WITH(ParseProcessed(Json(R"({"type": "processed", "stamp_ns": 50, "innovations": [
                                       {"type": "scan_match", "nis": 1, "dof": 3}]})"),
                                   50, {}, &more),
                    Contains("(none)"));
}

TEST_CASE("imu messages carry their samples in order and scan messages their ranges as float32",
          "[external][protocol]") {
  ImuSample a, b;
  a.stamp_ns = 1000000;
  b.stamp_ns = 2000000;
  a.sensor_id = b.sensor_id = "imu0";
  b.angular_velocity_rad_s = Eigen::Vector3d(0.1, -0.2, 1.0 / 3.0);
  b.linear_acceleration_m_s2 = Eigen::Vector3d(0.0, 0.5, 9.81);
  const nlohmann::ordered_json imu = ImuMessage({a, b});
  CHECK(imu["type"] == "imu");
  CHECK(imu["stamp_ns"] == 2000000);  // the last sample's
  REQUIRE(imu["samples"].size() == 2);
  CHECK(imu["samples"][1]["angular_velocity_rad_s"][2].get<double>() == 1.0 / 3.0);
  CHECK(imu["samples"][1]["linear_acceleration_m_s2"][2].get<double>() == 9.81);
  CHECK_FALSE(imu["samples"][0].contains("type"));

  LaserScan scan;
  scan.stamp_ns = 5;
  scan.sensor_id = "scanner";
  scan.time_increment_ns = 74074;
  scan.ranges_m = {1.25f, std::numeric_limits<float>::infinity(),
                   -std::numeric_limits<float>::infinity(),
                   std::numeric_limits<float>::quiet_NaN()};
  const nlohmann::ordered_json message = ScanMessage(scan, 0);
  CHECK(message["time_increment_ns"] == 74074);
  CHECK(message["ranges"]["count"] == 4);
  CHECK(message["ranges"]["bytes"] == 16);
  const std::string blob = ScanBlob(scan);
  REQUIRE(blob.size() == 16);
  float r[4];
  std::memcpy(r, blob.data(), 16);  // little-endian, as this machine
  CHECK(r[0] == 1.25f);
  CHECK((std::isinf(r[1]) && r[1] > 0));
  CHECK((std::isinf(r[2]) && r[2] < 0));
  CHECK(std::isnan(r[3]));
}

}  // namespace
}  // namespace corridorsim::external
