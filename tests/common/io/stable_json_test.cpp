// Tests common/io/stable_json.cpp: fixed rounding steps, the shortest decimal text, no -0, and the
// one pose convention (t rounded to 1e-6 m, q to 1e-9 with qw >= 0).
#include "common/io/stable_json.h"

#include <cmath>
#include <limits>
#include <numbers>

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

TEST_CASE("values round to their step and print as the short decimal", "[stable_json]") {
  CHECK(RoundToStep(2.30000049, json_steps::kMetres) == 2.3);
  CHECK(nlohmann::ordered_json(RoundToStep(2.3000004, json_steps::kMetres)).dump() == "2.3");
  CHECK(nlohmann::ordered_json(RoundToStep(0.1 + 0.2, json_steps::kRatio)).dump() == "0.3");
  CHECK(RoundToStep(1.23456789, json_steps::kPx) == 1.2346);
  CHECK(RoundToStep(-1.23456, json_steps::kPx) == -1.2346);
  CHECK(RoundToStep(0.123456789012, json_steps::kRad) == 0.12345679);
}

TEST_CASE("a value that rounds to zero is written without a sign", "[stable_json]") {
  const double r = RoundToStep(-4e-7, json_steps::kMetres);
  CHECK(r == 0.0);
  CHECK_FALSE(std::signbit(r));
  CHECK(nlohmann::ordered_json(RoundToStep(-0.0, json_steps::kRad)).dump() == "0.0");
}

TEST_CASE("non-finite values pass through and print as null", "[stable_json]") {
  CHECK(std::isnan(RoundToStep(std::numeric_limits<double>::quiet_NaN(), json_steps::kMetres)));
  CHECK(std::isinf(RoundToStep(std::numeric_limits<double>::infinity(), json_steps::kMetres)));
  CHECK(nlohmann::ordered_json(RoundToStep(std::nan(""), json_steps::kPx)).dump() == "null");
}

TEST_CASE("vectors are arrays of rounded components", "[stable_json]") {
  CHECK(RoundedJson(Eigen::Vector2d(1.00000049, -2e-7), json_steps::kMetres).dump() == "[1.0,0.0]");
  CHECK(RoundedJson(Eigen::Vector3d(0.5, 0.25, 1.23456), json_steps::kPx).dump() ==
        "[0.5,0.25,1.2346]");
}

TEST_CASE("text that is not UTF-8 is written with U+FFFD, not thrown at", "[stable_json]") {
  // An external program's Latin-1 output, a plugin's message, a file name: in values and keys.
  nlohmann::ordered_json j;
  j["reason"] = std::string("error: caf\xE9 \xFF\xFE end");
  j[std::string("file_\xE9")] = 1;
  j["ok"] = "\xE5\xA4\xB1 \x01";
  CHECK_THROWS(j.dump());  // what a plain dump does after all the work
  const std::string fffd = "\xEF\xBF\xBD";
  CHECK(JsonText(j) == "{\"reason\":\"error: caf" + fffd + " " + fffd + fffd + " end\",\"file_" +
                           fffd + "\":1,\"ok\":\"\xE5\xA4\xB1 \\u0001\"}");
  CHECK(JsonFileText(nlohmann::json{{"a", "\xE9"}}) == "{\n  \"a\": \"" + fffd + "\"\n}\n");
  // Valid text is unchanged: the same bytes as dump().
  const nlohmann::ordered_json valid = {{"name", "\xE5\xA4\xB1 <!--<script>"}, {"x", 0.5}};
  CHECK(JsonFileText(valid) == valid.dump(2) + "\n");
}

TEST_CASE("RoundNumbers rounds every number of a document", "[stable_json]") {
  nlohmann::ordered_json j = {
      {"a", 0.1 + 0.2}, {"b", {{"c", 30.000000000000004}, {"d", {1.0000004, 7}}}}, {"text", "x"}};
  RoundNumbers(j, json_steps::kSeconds);
  CHECK(j.dump() == "{\"a\":0.3,\"b\":{\"c\":30.0,\"d\":[1.0,7]},\"text\":\"x\"}");
}

TEST_CASE("poses are t in metres and q = [qx, qy, qz, qw] with qw >= 0", "[stable_json]") {
  // A half turn and a bit about z: Eigen's quaternion for it may carry either sign; the JSON has
  // qw >= 0 and the same rotation.
  const double yaw = 0.9 * std::numbers::pi;
  const Eigen::Quaterniond q(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  for (const double sign : {1.0, -1.0}) {
    INFO("sign " << sign);
    const Eigen::Quaterniond signed_q(sign * q.w(), sign * q.x(), sign * q.y(), sign * q.z());
    const SE3 pose(signed_q, Eigen::Vector3d(1.0000004, -2.5, 3e-7));
    const nlohmann::ordered_json j = PoseJson(pose);
    REQUIRE(j.size() == 2);
    CHECK(j.begin().key() == "t");
    CHECK(j["t"].dump() == "[1.0,-2.5,0.0]");
    REQUIRE(j["q"].size() == 4);
    CHECK(j["q"][3].get<double>() >= 0.0);
    CHECK(j["q"][0].get<double>() == 0.0);
    CHECK(j["q"][1].get<double>() == 0.0);
    CHECK(j["q"][2].get<double>() == RoundToStep(std::sin(yaw / 2), json_steps::kUnitVector));
    CHECK(j["q"][3].get<double>() == RoundToStep(std::cos(yaw / 2), json_steps::kUnitVector));
  }
}

}  // namespace
}  // namespace corridorsim
