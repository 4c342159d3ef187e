// Tests harness/workbench/detect.cpp: the inputs read and checked (PNG, bounds, the registered
// depth), and the document's sections per camera, in-process (the command itself:
// cli_detect_test.py).
#include "harness/workbench/detect.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "common/io/atomic_file.h"
#include "harness/run/frame_io.h"
#include "tests/support/expect_input_error.h"
#include "tests/support/scratch_dir.h"
#include "worlds/image_io.h"

namespace corridorsim {
namespace {

// A grey image with a bright square (four Harris corners) and a 16-bit depth image of it.
Image8 Square(int width, int height) {
  Image8 image(width, height, 3);
  for (int y = 20; y < 44; ++y) {
    for (int x = 30; x < 60; ++x) {
      for (int c = 0; c < 3; ++c) image.Pixel(x, y)[c] = 220;
    }
  }
  return image;
}

TEST_CASE("LoadDetectInput reads the image and the registered depth in metres", "[harness]") {
  test::ScratchDir dir("detect_load");
  const Image8 image = Square(80, 64);
  WriteFileAtomic(dir.path() / "rgb.png", EncodePng(image, "rgb.png"));
  std::vector<std::uint16_t> depth(80 * 64, 10000);  // 2 m
  depth[0] = 0;                                      // invalid
  WriteFileAtomic(dir.path() / "depth.png", EncodePng16(80, 64, 1, depth, "depth.png"));

  DetectRequest request;
  request.image_file = dir.path() / "rgb.png";
  request.depth_file = dir.path() / "depth.png";
  const DetectInput input = LoadDetectInput(request);
  CHECK(input.rgb.data == image.data);
  REQUIRE(input.depth_m);
  CHECK(input.depth_m->at(1, 0) == Approx(2.0));
  CHECK(input.depth_m->at(0, 0) == 0.0f);

  Image8 overlay;
  const nlohmann::ordered_json doc = RunDetect(input, &overlay);
  CHECK(doc["camera"] == "front");
  CHECK(doc["depth"] == true);
  CHECK(doc.contains("vanishing_point"));
  CHECK(doc["vanishing_point"]["found"] == false);  // a square has no vanishing point
  CHECK(doc["corners"]["count"] == 4);
  CHECK(doc["corners"]["with_depth"] == 4);
  CHECK(doc["corners"]["items"][0]["depth_m"] == 2.0);
  CHECK(overlay.width == 80);
  CHECK(overlay.height == 64);
  CHECK(overlay.data != image.data);  // the corners are drawn

  DetectInput lateral = input;
  lateral.camera = DetectCamera::kLateral;
  lateral.depth_m.reset();
  const nlohmann::ordered_json side = RunDetect(lateral, nullptr);
  CHECK(side["camera"] == "lateral");
  CHECK_FALSE(side.contains("vanishing_point"));
  CHECK(side["corners"]["items"][0]["depth_m"].is_null());
}

TEST_CASE("LoadDetectInput refuses bad files, naming them", "[harness]") {
  test::ScratchDir dir("detect_bad");
  const auto error_of = [&](const std::string& image, const std::string& depth) {
    DetectRequest request;
    request.image_file = dir.path() / image;
    if (!depth.empty()) request.depth_file = dir.path() / depth;
    return std::string(test::InputErrorOf([&] { LoadDetectInput(request); }).what());
  };
  WriteFileAtomic(dir.path() / "rgb.png", EncodePng(Square(80, 64), "rgb.png"));
  WriteFileAtomic(dir.path() / "text.png", "not a png\n");
  WriteFileAtomic(dir.path() / "small_depth.png",
                  EncodePng16(40, 32, 1, std::vector<std::uint16_t>(40 * 32, 5000), "d"));
  WriteFileAtomic(dir.path() / "rgb_depth.png", EncodePng(Square(80, 64), "d"));
  // A PNG header that claims 9000 x 1 px: refused before any pixel is decoded.
  std::string huge = EncodePng(Image8(1, 1, 1), "h");
  huge[16] = 0;
  huge[17] = 0;
  huge[18] = 0x23;
  huge[19] = 0x28;  // 9000
  WriteFileAtomic(dir.path() / "huge.png", huge);

  CHECK_THAT(error_of("missing.png", ""), Catch::Contains("missing.png: cannot be opened"));
  CHECK_THAT(error_of("text.png", ""), Catch::Contains("text.png: is not a PNG image"));
  CHECK_THAT(error_of("huge.png", ""), Catch::Contains("huge.png: is 9000x1 px"));
  CHECK_THAT(error_of("rgb.png", "small_depth.png"),
             Catch::Contains("small_depth.png: --depth: the depth image is 40x32 px"));
  CHECK_THAT(error_of("rgb.png", "rgb_depth.png"),
             Catch::Contains("rgb_depth.png: --depth: expected a 16-bit one-channel PNG"));
  CHECK(DetectCameraName(DetectCamera::kLateral) == "lateral");
}

TEST_CASE("detect --camera upward: lamps through the camera's model, bad intrinsics named",
          "[harness][lamps]") {
  test::ScratchDir dir("detect_upward");
  // A bright disc on a grey ceiling, 640x480 (the default upward camera's size) and 320x240.
  const auto ceiling = [](int width, int height) {
    Image8 image(width, height, 3);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        const bool lamp = std::hypot(x - 0.5 * width, y - 0.5 * height) < 20.0;
        for (int c = 0; c < 3; ++c) image.Pixel(x, y)[c] = lamp ? 255 : 150;
      }
    }
    return image;
  };
  WriteFileAtomic(dir.path() / "up.png", EncodePng(ceiling(640, 480), "up.png"));
  WriteFileAtomic(dir.path() / "small.png", EncodePng(ceiling(320, 240), "small.png"));
  DetectRequest request;
  request.image_file = dir.path() / "up.png";
  request.camera = DetectCamera::kUpward;
  const DetectInput input = LoadDetectInput(request);
  REQUIRE(input.model);
  CHECK(input.model->name() == "kannala_brandt");
  const nlohmann::ordered_json doc = RunDetect(input, nullptr);
  CHECK(doc["camera"] == "upward");
  CHECK(doc["model"] == "kannala_brandt");
  REQUIRE(doc["lamps"]["lamps"].size() == 1);
  CHECK(doc["lamps"]["lamps"][0]["center_px"][0].get<double>() == Approx(319.5).margin(0.5));
  CHECK(doc["lamps"]["lamps"][0]["radius_px"].get<double>() == Approx(20.0).margin(1.0));
  CHECK(doc.contains("corners"));

  // Another size needs its model; a model of the wrong size or a broken file is named.
  request.image_file = dir.path() / "small.png";
  CHECK_THAT(test::InputErrorOf([&] { LoadDetectInput(request); }).what(),
             Catch::Contains("small.png: --camera upward: the image is 320x240 px"));
  const std::string model_320 =
      "\"model\": \"kannala_brandt\", \"width\": 320, \"height\": 240, \"fx\": 125.0, "
      "\"fy\": 125.0, \"cx\": 159.5, \"cy\": 119.5, \"distortion\": [0, 0, 0, 0]";
  // A dataset's intrinsics.json (the model and the mount), and snapshot's (every camera of the
  // rig by name: the upward one is used).
  WriteFileAtomic(
      dir.path() / "k.json",
      "{" + model_320 + ", \"robot_from_camera\": {\"t\": [0, 0, 0.4], \"q\": [0, 0, 0, 1]}}");
  WriteFileAtomic(dir.path() / "rig.json", "{\"upward\": {" + model_320 + "}}");
  for (const char* file : {"k.json", "rig.json"}) {
    INFO(file);
    request.intrinsics_file = dir.path() / file;
    const DetectInput small = LoadDetectInput(request);
    REQUIRE(small.model);
    CHECK(small.model->width() == 320);
  }
  WriteFileAtomic(dir.path() / "rig_bad.json", "{\"upward\": 3}");
  request.intrinsics_file = dir.path() / "rig_bad.json";
  CHECK_THAT(test::InputErrorOf([&] { LoadDetectInput(request); }).what(),
             Catch::Contains("rig_bad.json: upward: expected a JSON object"));
  request.intrinsics_file = dir.path() / "k.json";
  request.image_file = dir.path() / "up.png";
  CHECK_THAT(test::InputErrorOf([&] { LoadDetectInput(request); }).what(),
             Catch::Contains("k.json: width: the model is 320x240 px, the image 640x480"));
  WriteFileAtomic(dir.path() / "bad.json", "{\"model\": \"fisheye9\"}");
  request.intrinsics_file = dir.path() / "bad.json";
  CHECK_THAT(test::InputErrorOf([&] { LoadDetectInput(request); }).what(),
             Catch::Contains("bad.json"));
  WriteFileAtomic(dir.path() / "list.json", "[1, 2]");
  request.intrinsics_file = dir.path() / "list.json";
  CHECK_THAT(test::InputErrorOf([&] { LoadDetectInput(request); }).what(),
             Catch::Contains("list.json: expected a JSON object"));
  CHECK(DetectCameraName(DetectCamera::kUpward) == "upward");
}

}  // namespace
}  // namespace corridorsim
