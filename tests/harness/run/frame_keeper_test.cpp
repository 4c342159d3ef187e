#include "harness/run/frame_keeper.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "sim/simulation.h"
#include "worlds/image_io.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;

// A noisy 640x480 RGB frame (JPEG cannot shrink noise much: each kept frame costs real bytes).
sim::CameraMessage NoisyFrame(TimeNs stamp, std::uint32_t seed) {
  sim::CameraMessage m;
  m.stamp_ns = stamp;
  m.frame.rgb = Image8(640, 480, 3);
  std::mt19937 random(seed);
  for (std::uint8_t& v : m.frame.rgb.data) v = static_cast<std::uint8_t>(random() & 0xff);
  return m;
}

// Feeds `count` frames of camera "upward" (and a dropped slot every 7th) at 5 Hz.
void Feed(FrameKeeper& keeper, int count) {
  for (int i = 0; i < count; ++i) {
    const sim::CameraMessage frame =
        NoisyFrame(TimeNs{200'000'000} * i, static_cast<std::uint32_t>(i));
    CameraSet set;
    set.stamp_ns = frame.stamp_ns;
    set.cameras.push_back({"upward", 0, &frame});
    if (i % 7 == 3) set.cameras.push_back({"front", 1, nullptr});  // dropped: nothing kept
    keeper.OnCameraSet(set);
  }
}

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST_CASE("FrameKeeper keeps every frame while they fit the budget", "[run][frames]") {
  FrameKeeper keeper(100'000'000);
  Feed(keeper, 10);
  CHECK(keeper.kept_frames() == 10);
  CHECK(keeper.stride() == 1);
}

TEST_CASE("FrameKeeper thins by doubling its stride and stays within the budget", "[run][frames]") {
  // A budget of three and a half frames' JPEGs (noisy frames: all of about one size).
  double one_scale = 0.0;
  const std::size_t one = EncodeJpegShrunk(NoisyFrame(0, 0).frame.rgb, FrameKeeper::kMaxWidthPx,
                                           FrameKeeper::kJpegQuality, "test", &one_scale)
                              .size();
  CHECK(one_scale == 0.5);
  const std::size_t budget = one * 7 / 2;
  FrameKeeper keeper(budget);
  Feed(keeper, 40);
  CHECK(keeper.kept_bytes() <= budget);
  CHECK(keeper.stride() > 1);
  CHECK(keeper.kept_frames() >= 2);

  const fs::path dir = fs::temp_directory_path() / "corridorsim_frame_keeper_test";
  fs::remove_all(dir);
  keeper.Write(dir);
  std::istringstream csv(ReadFile(dir / "frames.csv"));
  std::string line;
  std::getline(csv, line);
  CHECK(line == "camera,t_ns,file,scale,width,height");
  std::size_t rows = 0;
  std::size_t bytes = 0;
  while (std::getline(csv, line)) {
    ++rows;
    // upward,<t_ns>,upward_<t_ns>.jpg,0.5,640,480: the n-th frame at n * 0.2 s, n a multiple of
    // the stride.
    std::istringstream fields(line);
    std::string camera, stamp, file, scale, width, height;
    std::getline(fields, camera, ',');
    std::getline(fields, stamp, ',');
    std::getline(fields, file, ',');
    std::getline(fields, scale, ',');
    std::getline(fields, width, ',');
    std::getline(fields, height, ',');
    CHECK(camera == "upward");
    CHECK(file == "upward_" + stamp + ".jpg");
    CHECK(scale == "0.5");
    CHECK(width == "640");
    CHECK(height == "480");
    const std::int64_t n = std::stoll(stamp) / 200'000'000;
    CHECK(n % static_cast<std::int64_t>(keeper.stride()) == 0);
    const std::string jpeg = ReadFile(dir / file);
    REQUIRE(jpeg.size() > 3);
    CHECK(static_cast<unsigned char>(jpeg[0]) == 0xFF);  // JPEG SOI marker
    CHECK(static_cast<unsigned char>(jpeg[1]) == 0xD8);
    bytes += jpeg.size();
  }
  CHECK(rows == keeper.kept_frames());
  CHECK(bytes == keeper.kept_bytes());

  // The same frames give the same files: what is kept depends on order and bytes only.
  FrameKeeper again(budget);
  Feed(again, 40);
  const fs::path dir2 = dir.string() + "_again";
  fs::remove_all(dir2);
  again.Write(dir2);
  CHECK(ReadFile(dir / "frames.csv") == ReadFile(dir2 / "frames.csv"));
  fs::remove_all(dir);
  fs::remove_all(dir2);
}

TEST_CASE("FrameKeeper never thins away its only frame", "[run][frames]") {
  FrameKeeper keeper(1);  // smaller than any JPEG
  Feed(keeper, 3);
  CHECK(keeper.kept_frames() == 1);
}

}  // namespace
}  // namespace corridorsim
