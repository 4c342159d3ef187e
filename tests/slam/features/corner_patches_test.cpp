// slam/features/corner_patches.cpp: FAST and Harris corners of a drawn image, their spacing and
// order, and patches sampled turned by an angle, which match the same place of the image turned
// by that angle (what lets the upward pipeline match corners after the robot turns).
#include "slam/features/corner_patches.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "common/pose.h"
#include "render/frame_truth.h"
#include "slam/features/image_conversion.h"
#include "tests/support/upward_frames.h"
#include "worlds/world.h"

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

// Appends the distance from each tile-seam crossing of the frame truth to the nearest corner,
// for the crossings that have a corner within 5 px (the others were not detected).
void AddCrossingErrors(const std::vector<slam::CornerWithResponse>& corners,
                       const render::FrameTruth& truth, std::vector<double>* errors) {
  for (const render::CornerTruth& t : truth.corners) {
    if (t.kind != worlds::CornerKind::kTileSeam) continue;
    double best = 99.0;
    for (const auto& c : corners) best = std::min(best, (c.pixel_px - t.pixel).norm());
    if (best <= 5.0) errors->push_back(best);
  }
}

double Median(std::vector<double> v) {
  REQUIRE(!v.empty());
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

TEST_CASE("corners: FAST corners refined to sub-pixel sit on the rendered seam crossings",
          "[corners][render]") {
  // FAST fires on the four tile corners around a crossing of the seams, 2-3 px from its centre;
  // cornerSubPix moves the kept one onto the crossing. Scored on rendered upward frames of
  // scenarios/p3_doors.yaml's corridor against the frame truth's tile-seam crossings.
  worlds::WorldOptions world_options;
  world_options.length_m = 40.0;
  const worlds::World world = worlds::Generate(world_options, 3);
  test::UpwardFrames frames(world);
  slam::CornerPatchOptions o;  // FAST, refined by default
  REQUIRE(o.fast_subpixel_half_px > 0);
  std::vector<double> refined, integer;
  for (int k = 0; k < 4; ++k) {
    const SE3 world_from_robot = SE3::FromSE2(SE2(5.0 + 7.3 * k, 0.1 * (k % 3 - 1), 0.4 * k));
    render::CameraFrame frame;
    const render::FrameTruth truth = frames.Render(world_from_robot, std::uint64_t(k), &frame);
    const cv::Mat grey = slam::GreyMat(frame.rgb);
    o.fast_subpixel_half_px = slam::CornerPatchOptions{}.fast_subpixel_half_px;
    AddCrossingErrors(slam::DetectCorners(grey, o), truth, &refined);
    o.fast_subpixel_half_px = 0;
    AddCrossingErrors(slam::DetectCorners(grey, o), truth, &integer);
    // Refinement keeps every corner inside the patch margin, even with a wide window.
    o.fast_subpixel_half_px = 10;
    for (const auto& c : slam::DetectCorners(grey, o)) {
      CHECK(c.pixel_px.x() >= o.patch_half_px + 2);
      CHECK(c.pixel_px.y() >= o.patch_half_px + 2);
      CHECK(c.pixel_px.x() < grey.cols - o.patch_half_px - 2);
      CHECK(c.pixel_px.y() < grey.rows - o.patch_half_px - 2);
    }
  }
  INFO("crossings with a corner: refined " << refined.size() << ", median error " << Median(refined)
                                           << " px; integer " << integer.size() << ", median error "
                                           << Median(integer) << " px");
  CHECK(refined.size() >= 20);
  CHECK(Median(refined) < 0.5);
  CHECK(Median(integer) > 1.5);
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
