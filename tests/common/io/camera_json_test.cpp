// Tests common/io/camera_json.cpp: camera models to JSON and back, in intrinsics.json's form.
#include "common/io/camera_json.h"

#include <numbers>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "common/error.h"
#include "tests/support/test_cameras.h"

namespace corridorsim {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

PinholeRadTan DistortedPinhole() {
  PinholeRadTan camera = PinholeRadTan::FromFov(640, 480, 58.0 * kRadPerDeg);
  camera.fy *= 1.001;
  return test::WithWebcamDistortion(camera);
}

KannalaBrandt Fisheye() {
  KannalaBrandt camera = KannalaBrandt::FromFov(640, 480, 110.0 * kRadPerDeg);
  camera.cx += 1.3;
  return test::WithSmallFisheyeDistortion(camera);
}

// The problem CameraModelFromJson reports for `text` (fails the test if it accepts it).
OptionsProblem ProblemOf(const std::string& text) {
  try {
    CameraModelFromJson(nlohmann::json::parse(text));
  } catch (const OptionsError& e) {
    return e.problem();
  }
  FAIL("no OptionsError for " << text);
  return {};
}

const char* const kFisheyeJson =
    R"({"model": "kannala_brandt", "width": 64, "height": 48, "fx": 25.0, "fy": 25.0, )"
    R"("cx": 31.5, "cy": 23.5, "distortion": [0.01, 0, 0, 0]})";

TEST_CASE("camera models survive JSON text and back bit for bit", "[camera][json]") {
  for (const CameraModel& model : {CameraModel(DistortedPinhole()), CameraModel(Fisheye()),
                                   CameraModel(PinholeRadTan::FromFov(64, 48, 1.0))}) {
    INFO(CameraModelToJson(model).dump());
    CHECK(CameraModelFromJson(CameraModelToJson(model)) == model);
    CHECK(CameraModelFromJson(nlohmann::json::parse(CameraModelToJson(model).dump())) == model);
  }
}

TEST_CASE("CameraModelToJson writes intrinsics.json's keys in their order", "[camera][json]") {
  const PinholeRadTan pinhole{
      .width = 64, .height = 48, .fx = 50.0, .fy = 50.0, .cx = 31.5, .cy = 23.5, .k1 = -0.1};
  CHECK(CameraModelToJson(pinhole).dump() ==
        R"({"model":"pinhole_radtan","width":64,"height":48,"fx":50.0,"fy":50.0,"cx":31.5,)"
        R"("cy":23.5,"distortion":[-0.1,0.0,0.0,0.0,0.0]})");
  const CameraModel fisheye = CameraModelFromJson(nlohmann::json::parse(kFisheyeJson));
  REQUIRE(fisheye.kannala_brandt() != nullptr);
  CHECK(fisheye.kannala_brandt()->k1 == 0.01);
  CHECK(CameraModelToJson(fisheye).dump() ==
        R"({"model":"kannala_brandt","width":64,"height":48,"fx":25.0,"fy":25.0,"cx":31.5,)"
        R"("cy":23.5,"distortion":[0.01,0.0,0.0,0.0]})");
}

TEST_CASE("CameraModelFromJson rejects malformed models naming the key", "[camera][json]") {
  const auto with = [](const std::string& from, const std::string& to) {
    std::string text = kFisheyeJson;
    const std::size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    return text.replace(at, from.size(), to);
  };
  CHECK(ProblemOf("[1, 2]").key == "camera");
  CHECK(ProblemOf(with(R"("width": 64, )", "")).key == "width");
  CHECK(ProblemOf(with(R"("width": 64)", R"("width": 64.5)")).key == "width");
  CHECK(ProblemOf(with(R"("width": 64)", R"("width": -64)")).key == "width");
  CHECK(ProblemOf(with(R"("fx": 25.0)", R"("fx": "25")")).key == "fx");
  CHECK(ProblemOf(with(R"("cy": 23.5, )", R"("cy": 23.5, "k1": 0.1, )")).key == "k1");
  const OptionsProblem model = ProblemOf(with("kannala_brandt", "fisheye"));
  CHECK(model.key == "model");
  CHECK_THAT(model.message, Catch::Contains("\"pinhole_radtan\" or \"kannala_brandt\""));
  const OptionsProblem length = ProblemOf(with("[0.01, 0, 0, 0]", "[0.01, 0, 0, 0, 0]"));
  CHECK(length.key == "distortion");
  CHECK_THAT(length.message, Catch::Contains("[k1, k2, k3, k4]"));
  CHECK(ProblemOf(with("[0.01, 0, 0, 0]", R"([0.01, 0, null, 0])")).key == "distortion");
  // Well-formed but impossible: CameraModel::Check()'s message under "model".
  const OptionsProblem check = ProblemOf(with(R"("width": 64)", R"("width": 0)"));
  CHECK(check.key == "model");
  CHECK_THAT(check.message, Catch::Contains("image size must be positive"));
}

TEST_CASE("an intrinsics.json entry reads as it is, mount and depth scale passed over",
          "[camera][json]") {
  nlohmann::ordered_json entry = CameraModelToJson(DistortedPinhole());
  entry["robot_from_camera"] =
      nlohmann::json::parse(R"({"t": [0.18, 0, 0.45], "q": [0, 0, 0, 1]})");
  entry["depth_scale"] = 5000.0;
  CHECK(CameraModelFromJson(entry) == CameraModel(DistortedPinhole()));
  CHECK(CameraModelFromJson(nlohmann::json::parse(entry.dump())) ==
        CameraModel(DistortedPinhole()));
  // They are checked for what they are.
  nlohmann::ordered_json bad_mount = entry;
  bad_mount["robot_from_camera"] = 3;
  CHECK(ProblemOf(bad_mount.dump()).key == "robot_from_camera");
  nlohmann::ordered_json bad_scale = entry;
  bad_scale["depth_scale"] = -1;
  CHECK(ProblemOf(bad_scale.dump()).key == "depth_scale");
  bad_scale["depth_scale"] = "5000";
  CHECK(ProblemOf(bad_scale.dump()).key == "depth_scale");
}

TEST_CASE("CameraModelFromIntrinsicsJson reads one camera's entry or picks it by id",
          "[camera][json]") {
  nlohmann::ordered_json one = CameraModelToJson(Fisheye());
  one["robot_from_camera"] = nlohmann::json::parse(R"({"t": [0, 0, 0.4], "q": [0, 0, 0, 1]})");
  CHECK(CameraModelFromIntrinsicsJson(one, "upward") == CameraModel(Fisheye()));
  nlohmann::ordered_json rig;
  rig["front"] = CameraModelToJson(DistortedPinhole());
  rig["front"]["depth_scale"] = 5000.0;
  rig["upward"] = one;
  CHECK(CameraModelFromIntrinsicsJson(rig, "upward") == CameraModel(Fisheye()));
  CHECK(CameraModelFromIntrinsicsJson(rig, "front") == CameraModel(DistortedPinhole()));
  const auto problem = [&](const nlohmann::ordered_json& json, const std::string& camera) {
    try {
      CameraModelFromIntrinsicsJson(json, camera);
    } catch (const OptionsError& e) {
      return e.problem();
    }
    FAIL("no OptionsError for " << camera << " in " << json.dump());
    return OptionsProblem{};
  };
  CHECK(problem(rig, "lateral").key == "lateral");
  rig["front"]["fx"] = "x";
  CHECK(problem(rig, "front").key == "front.fx");
  rig["front"] = 3;
  CHECK(problem(rig, "front").key == "front");
  CHECK(problem(nlohmann::ordered_json::array(), "front").key == "camera");
}

}  // namespace
}  // namespace corridorsim
