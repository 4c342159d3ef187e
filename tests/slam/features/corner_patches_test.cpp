// slam/features/corner_patches.cpp: FAST and Harris corners of a drawn image, their spacing and
// order, and patches sampled turned by an angle, which match the same place of the image turned
// by that angle (what lets the upward pipeline match corners after the robot turns).
#include "slam/features/corner_patches.h"

#include <cmath>
#include <numbers>

#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

namespace corridorsim {
namespace {

// A grey image with a bright square (four corners) and an L-shaped mark beside it, blurred as a
// lens blurs (FAST finds no corner on a perfectly sharp square: its circle's pixels on the
// square's edges equal the centre's).
cv::Mat Drawing() {
  cv::Mat grey(200, 240, CV_8UC1, cv::Scalar(60));
  cv::rectangle(grey, cv::Rect(60, 50, 80, 70), cv::Scalar(200), cv::FILLED);
  cv::rectangle(grey, cv::Rect(170, 120, 30, 8), cv::Scalar(220), cv::FILLED);
  cv::rectangle(grey, cv::Rect(170, 120, 8, 40), cv::Scalar(220), cv::FILLED);
  cv::GaussianBlur(grey, grey, cv::Size(5, 5), 1.0);
  return grey;
}

TEST_CASE("corners: FAST and Harris find the square's corners, strongest first, spaced",
          "[corners]") {
  for (const slam::CornerDetector detector :
       {slam::CornerDetector::kFast, slam::CornerDetector::kHarris}) {
    slam::CornerPatchOptions o;
    o.detector = detector;
    const std::vector<slam::CornerWithResponse> corners = slam::DetectCorners(Drawing(), o);
    REQUIRE(corners.size() >= 4);
    for (std::size_t i = 1; i < corners.size(); ++i) {
      CHECK(corners[i - 1].response >= corners[i].response);
      for (std::size_t j = 0; j < i; ++j) {
        CHECK((corners[i].pixel_px - corners[j].pixel_px).norm() >= o.min_distance_px);
      }
    }
    for (const Eigen::Vector2d& c : {Eigen::Vector2d(60, 50), Eigen::Vector2d(139, 50),
                                     Eigen::Vector2d(60, 119), Eigen::Vector2d(139, 119)}) {
      const bool found = std::any_of(corners.begin(), corners.end(),
                                     [&](const auto& k) { return (k.pixel_px - c).norm() <= 3.0; });
      CHECK(found);
    }
    o.max_corners = 2;
    CHECK(slam::DetectCorners(Drawing(), o).size() == 2);
  }
  // A flat image has none.
  CHECK(slam::DetectCorners(cv::Mat(100, 100, CV_8UC1, cv::Scalar(90)), {}).empty());
}

TEST_CASE("patches: unit vectors; a turned image matches a patch turned by the same angle",
          "[corners]") {
  const cv::Mat grey = Drawing();
  const Eigen::Vector2d corner(139, 119);  // the square's bottom-right corner
  const std::optional<std::vector<float>> patch = slam::SamplePatch(grey, corner, 0.0, 5);
  REQUIRE(patch);
  CHECK(slam::PatchCorrelation(*patch, *patch) == Approx(1.0));
  // Turn the image by 30 deg about the corner: the patch sampled turned by 30 deg matches.
  const double angle = 30.0 * std::numbers::pi / 180.0;
  cv::Mat turned;
  // cv::getRotationMatrix2D turns counter-clockwise on screen for a positive angle; with y down
  // that is a turn of -angle from image x towards image y.
  cv::warpAffine(grey, turned, cv::getRotationMatrix2D(cv::Point2f(139, 119), 30.0, 1.0),
                 grey.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  const std::optional<std::vector<float>> aligned = slam::SamplePatch(turned, corner, -angle, 5);
  const std::optional<std::vector<float>> unaligned = slam::SamplePatch(turned, corner, 0.0, 5);
  REQUIRE(aligned);
  REQUIRE(unaligned);
  CHECK(slam::PatchCorrelation(*patch, *aligned) > 0.95);
  CHECK(slam::PatchCorrelation(*patch, *unaligned) < slam::PatchCorrelation(*patch, *aligned));
  // Another corner of the square looks different.
  const std::optional<std::vector<float>> other =
      slam::SamplePatch(grey, Eigen::Vector2d(60, 50), 0.0, 5);
  REQUIRE(other);
  CHECK(slam::PatchCorrelation(*patch, *other) < 0.5);
  // A flat patch and one leaving the image have none.
  CHECK_FALSE(slam::SamplePatch(grey, Eigen::Vector2d(20, 20), 0.0, 5));
  CHECK_FALSE(slam::SamplePatch(grey, Eigen::Vector2d(2, 100), 0.0, 5));
}

}  // namespace
}  // namespace corridorsim
