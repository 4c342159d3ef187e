// Tests slam/features/harris_corners.cpp: the corners of a synthetic checkerboard, the selection
// rules (count, spacing, order) and the registered depth looked up at each corner.
#include "slam/features/harris_corners.h"

#include <cmath>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "slam/features/image_conversion.h"
#include "tests/support/broken_options.h"
#include "tests/support/feature_tolerances.h"

namespace corridorsim::slam {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr int kSquarePx = 40;
constexpr int kBoardX = 80, kBoardY = 60;  // the board's top-left pixel
constexpr int kSquaresX = 8, kSquaresY = 6;

// A black-and-white checkerboard on mid grey. Square (i, j) covers pixels [kBoardX + 40 i,
// kBoardX + 40 (i + 1)) in x, so the edge between two squares lies at pixel coordinate
// kBoardX + 40 i - 0.5 (pixel centres at integers).
Image8 Checkerboard() {
  cv::Mat image(kHeight, kWidth, CV_8UC3, cv::Scalar(128, 128, 128));
  for (int j = 0; j < kSquaresY; ++j) {
    for (int i = 0; i < kSquaresX; ++i) {
      const int v = (i + j) % 2 ? 230 : 25;
      cv::rectangle(
          image, cv::Rect(kBoardX + kSquarePx * i, kBoardY + kSquarePx * j, kSquarePx, kSquarePx),
          cv::Scalar(v, v, v), cv::FILLED);
    }
  }
  return ImageFromMat(image);
}

std::vector<Eigen::Vector2d> InnerCorners() {
  std::vector<Eigen::Vector2d> corners;
  for (int j = 1; j < kSquaresY; ++j) {
    for (int i = 1; i < kSquaresX; ++i) {
      corners.emplace_back(kBoardX + kSquarePx * i - 0.5, kBoardY + kSquarePx * j - 0.5);
    }
  }
  return corners;
}

double NearestDistance(const std::vector<HarrisCorner>& corners, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const HarrisCorner& c : corners) best = std::min(best, (c.pixel_px - p).norm());
  return best;
}

TEST_CASE("every inner corner of a checkerboard is found within a pixel", "[slam][features]") {
  const Image8 board = Checkerboard();
  HarrisCornerOptions integer;
  integer.subpixel_half_window_px = 0;
  const std::vector<HarrisCorner> at_pixels = DetectHarrisCorners(board, nullptr, integer);
  const std::vector<HarrisCorner> refined =
      DetectHarrisCorners(board, nullptr, HarrisCornerOptions{});
  for (const Eigen::Vector2d& truth : InnerCorners()) {
    INFO("corner at (" << truth.x() << ", " << truth.y() << ")");
    CHECK(NearestDistance(at_pixels, truth) <= test::kHarrisIntegerPx);
    CHECK(NearestDistance(refined, truth) <= test::kHarrisSubpixelPx);
  }
  // Nothing but the board's corners (inner, and where its border meets the background).
  for (const HarrisCorner& c : refined) {
    const double gx = (c.pixel_px.x() + 0.5 - kBoardX) / kSquarePx;
    const double gy = (c.pixel_px.y() + 0.5 - kBoardY) / kSquarePx;
    CHECK(std::abs(gx - std::round(gx)) * kSquarePx < 1.0);
    CHECK(std::abs(gy - std::round(gy)) * kSquarePx < 1.0);
    CHECK_FALSE(c.depth_m);  // no depth image given
  }
}

TEST_CASE("corners come strongest first, spaced and counted as asked", "[slam][features]") {
  const Image8 board = Checkerboard();
  HarrisCornerOptions options;
  options.max_corners = 10;
  const std::vector<HarrisCorner> corners = DetectHarrisCorners(board, nullptr, options);
  REQUIRE(corners.size() == 10);
  for (std::size_t i = 1; i < corners.size(); ++i) {
    CHECK(corners[i - 1].response >= corners[i].response);
  }
  options.max_corners = 1000;
  options.min_distance_px = 60.0;  // more than a square: neighbours exclude each other
  options.subpixel_half_window_px = 0;
  const std::vector<HarrisCorner> spaced = DetectHarrisCorners(board, nullptr, options);
  REQUIRE(spaced.size() > 1);
  for (std::size_t i = 0; i < spaced.size(); ++i) {
    for (std::size_t k = i + 1; k < spaced.size(); ++k) {
      CHECK((spaced[i].pixel_px - spaced[k].pixel_px).norm() >= options.min_distance_px);
    }
  }
  CHECK(DetectHarrisCorners(Image8(kWidth, kHeight, 3), nullptr, HarrisCornerOptions{}).empty());
  // Deterministic: the same corners in the same order.
  const std::vector<HarrisCorner> again = DetectHarrisCorners(board, nullptr, options);
  REQUIRE(again.size() == spaced.size());
  for (std::size_t i = 0; i < spaced.size(); ++i) CHECK(again[i].pixel_px == spaced[i].pixel_px);
}

TEST_CASE("each corner's depth is the median of the valid depths around it", "[slam][features]") {
  const Image8 board = Checkerboard();
  // A depth ramp: the median of a 3x3 window of a linear ramp is its centre value.
  ImageF depth(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x)
      depth.at(x, y) = static_cast<float>(1.0 + 0.004 * x + 0.002 * y);
  }
  const std::vector<HarrisCorner> corners =
      DetectHarrisCorners(board, &depth, HarrisCornerOptions{});
  REQUIRE_FALSE(corners.empty());
  for (const HarrisCorner& c : corners) {
    REQUIRE(c.depth_m);
    const int x = static_cast<int>(std::lround(c.pixel_px.x()));
    const int y = static_cast<int>(std::lround(c.pixel_px.y()));
    CHECK(*c.depth_m == Approx(depth.at(x, y)).epsilon(1e-6));
  }

  // Zeros (invalid) in the depth image: no depth.
  const ImageF zeros(kWidth, kHeight, 0.0f);
  for (const HarrisCorner& c : DetectHarrisCorners(board, &zeros, HarrisCornerOptions{})) {
    CHECK_FALSE(c.depth_m);
  }
}

TEST_CASE("MedianDepth3x3 ignores invalid depths and clips the window", "[slam][features]") {
  ImageF depth(4, 3, 0.0f);
  CHECK_FALSE(MedianDepth3x3(depth, 1, 1));
  depth.at(0, 0) = 2.0f;
  CHECK(MedianDepth3x3(depth, 1, 1) == Approx(2.0));
  CHECK_FALSE(MedianDepth3x3(depth, 3, 2));  // (0, 0) is outside that window
  depth.at(1, 1) = 3.0f;
  depth.at(2, 1) = std::numeric_limits<float>::quiet_NaN();
  depth.at(2, 2) = -1.0f;
  CHECK(MedianDepth3x3(depth, 1, 1) == Approx(2.5));  // two valid: the mean of both
  depth.at(0, 1) = 10.0f;
  CHECK(MedianDepth3x3(depth, 1, 1) == Approx(3.0));  // {2, 3, 10}
  CHECK(MedianDepth3x3(depth, 0, 0) == Approx(3.0));  // corner window: {2, 10, 3}
}

TEST_CASE("Harris options: defaults pass and bounds are checked", "[slam][features]") {
  test::CheckEachBrokenOption<HarrisCornerOptions>({
      {[](HarrisCornerOptions& o) { o.max_corners = 0; }, "max_corners"},
      {[](HarrisCornerOptions& o) { o.quality_level = 0.0; }, "quality_level"},
      {[](HarrisCornerOptions& o) { o.block_size_px = 1; }, "block_size_px"},
  });
}

}  // namespace
}  // namespace corridorsim::slam
