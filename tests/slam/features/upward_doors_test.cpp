// slam/features/upward_doors.cpp: P3 section III-A's door candidates (vertical lines pointing at
// the principal point, columns, pairs, the bar's search area of eqs. 3-4) on drawn images, the
// degenerate frames, and rendered upward frames scored against the frame truth's column angles.
#include <cmath>
#include <numbers>

#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "common/random.h"
#include "render/camera_rig.h"
#include "render/frame_truth.h"
#include "slam/features/image_conversion.h"
#include "slam/features/upward_doors.h"
#include "tests/support/upward_frames.h"
#include "worlds/world.h"

namespace corridorsim {
namespace {

constexpr double kPi = std::numbers::pi;
const Eigen::Vector2d kCentre(319.5, 239.5);

Eigen::Vector2d Polar(double r, double angle) {
  return kCentre + r * Eigen::Vector2d(std::cos(angle), std::sin(angle));
}

cv::Point At(const Eigen::Vector2d& p) {
  return cv::Point(int(std::lround(p.x())), int(std::lround(p.y())));
}

// A ceiling-grey image with two dark columns (radial bands from radius 160 outwards) at the
// given angles and, if asked, a bar between their tops at `bar_radius_factor` of their radius.
cv::Mat DoorImage(double angle_a, double angle_b, std::optional<double> bar_radius_factor) {
  cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(190));
  for (const double angle : {angle_a, angle_b}) {
    cv::line(grey, At(Polar(160, angle)), At(Polar(330, angle)), cv::Scalar(60), 6, cv::LINE_AA);
  }
  if (bar_radius_factor) {
    const double r = 160 * *bar_radius_factor;
    cv::line(grey, At(Polar(r, angle_a)), At(Polar(r, angle_b)), cv::Scalar(60), 6, cv::LINE_AA);
  }
  return grey;
}

TEST_CASE("door candidates: two columns and their bar make one candidate with the columns' angles",
          "[doors]") {
  const slam::UpwardDoorDetection found =
      slam::DetectUpwardDoorCandidates(DoorImage(-0.4, 0.35, 1.0), kCentre, {});
  REQUIRE(found.columns.size() == 2);
  REQUIRE(found.candidates.size() == 1);
  const slam::UpwardDoorCandidate& c = found.candidates[0];
  // Column a is the first counter-clockwise (b lies less than 180 degrees on from it).
  CHECK(c.angle_a_rad == Approx(-0.4).margin(0.01));
  CHECK(c.angle_b_rad == Approx(0.35).margin(0.01));
  CHECK((c.top_a_px - kCentre).norm() == Approx(160).margin(6));
  CHECK(c.bar_coverage >= 0.6);
}

TEST_CASE("door candidates: no bar, or a line nearer the centre than the tops, is no door",
          "[doors]") {
  // Columns alone (P3 Fig. 6c).
  CHECK(slam::DetectUpwardDoorCandidates(DoorImage(-0.4, 0.35, std::nullopt), kCentre, {})
            .candidates.empty());
  // The wall's top edge between two columns of different doors: higher, so nearer the centre.
  CHECK(slam::DetectUpwardDoorCandidates(DoorImage(-0.4, 0.35, 0.78), kCentre, {})
            .candidates.empty());
  // Columns 100 degrees apart are not one door's.
  CHECK(
      slam::DetectUpwardDoorCandidates(DoorImage(-0.9, 0.85, 1.0), kCentre, {}).candidates.empty());
}

TEST_CASE("door candidates: a line not pointing at the centre is not a column", "[doors]") {
  cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(190));
  // Two parallel lines (a tile seam pair), not radial.
  cv::line(grey, cv::Point(450, 100), cv::Point(460, 300), cv::Scalar(60), 6, cv::LINE_AA);
  cv::line(grey, cv::Point(500, 100), cv::Point(510, 300), cv::Scalar(60), 6, cv::LINE_AA);
  const slam::UpwardDoorDetection found = slam::DetectUpwardDoorCandidates(grey, kCentre, {});
  CHECK(found.columns.empty());
  CHECK(found.candidates.empty());
}

TEST_CASE("door candidates: P3 eq. 4 bounds the bar's slope", "[doors]") {
  const Eigen::Vector2d p1 = kCentre + Eigen::Vector2d(100, 0);                      // angle 0
  const Eigen::Vector2d p2 = kCentre + 100 * Eigen::Vector2d(0.5, std::sqrt(0.75));  // 60 deg
  CHECK(slam::BarSlopeAllowed(p1, p2, p1, p2, kCentre));  // the chord itself
  CHECK(slam::BarSlopeAllowed(p2, p1, p1, p2, kCentre));  // either sense
  // Along the ray to p1 (t2 = 0): the range's end, theta1 + 180.
  CHECK(slam::BarSlopeAllowed(kCentre, p1, p1, p2, kCentre));
  // 45 degrees: neither sense lies in [theta2, theta1 + 180] = [60, 180].
  CHECK_FALSE(slam::BarSlopeAllowed(kCentre, kCentre + Eigen::Vector2d(1, 1), p1, p2, kCentre));
}

TEST_CASE("door candidates: black, flat and noise frames give none and do not fail", "[doors]") {
  CHECK(slam::DetectUpwardDoorCandidates(cv::Mat(480, 640, CV_8UC1, cv::Scalar(0)), kCentre, {})
            .candidates.empty());
  CHECK(slam::DetectUpwardDoorCandidates(cv::Mat(480, 640, CV_8UC1, cv::Scalar(128)), kCentre, {})
            .candidates.empty());
  cv::Mat noise(480, 640, CV_8UC1);
  RandomStream random(3, 0, "test.noise");
  for (int v = 0; v < noise.rows; ++v) {
    for (int u = 0; u < noise.cols; ++u)
      noise.at<std::uint8_t>(v, u) = std::uint8_t(random.UniformInt(0, 255));
  }
  const slam::UpwardDoorDetection found = slam::DetectUpwardDoorCandidates(noise, kCentre, {});
  CHECK(found.candidates.size() <= std::size_t(slam::UpwardDoorOptions{}.max_candidates));
  CHECK(slam::DetectUpwardDoorCandidates(cv::Mat(), kCentre, {}).candidates.empty());
}

TEST_CASE("door candidates: rendered upward frames, scored by the columns' image angles",
          "[doors][render]") {
  // P3 environment B (scenarios/p3_doors.yaml's world): doors open, closed and empty.
  worlds::WorldOptions world_options;
  world_options.length_m = 40.0;
  world_options.doors.count = 16;
  const worlds::World world = worlds::Generate(world_options, 1);
  test::UpwardFrames frames(world);
  const CameraModel& model = frames.model();
  int doors = 0, found = 0;
  for (int k = 0; k < 16; ++k) {
    const SE3 world_from_robot =
        SE3::FromSE2(SE2(2.0 + 2.3 * k, 0.1 * (k % 3 - 1), 0.05 * (k % 5 - 2)));
    render::CameraFrame frame;
    const render::FrameTruth truth = frames.Render(world_from_robot, std::uint64_t(k), &frame);
    const slam::UpwardDoorDetection detection = slam::DetectUpwardDoorCandidates(
        slam::GreyMat(frame.rgb), model.principal_point(), slam::UpwardDoorOptions{});
    for (const render::DoorTruth& t : truth.doors) {
      // Doors seen whole, from the side (a door right above the camera has no candidate, P3).
      const double span =
          std::abs(std::remainder(t.image_angle_a_rad - t.image_angle_b_rad, 2 * kPi));
      if (!t.visible || span < 0.25) continue;
      ++doors;
      const auto error = [](double a, double b) {
        return std::abs(std::remainder(a - b, 2 * kPi));
      };
      found += std::any_of(detection.candidates.begin(), detection.candidates.end(),
                           [&](const slam::UpwardDoorCandidate& c) {
                             return std::max(error(c.angle_a_rad, t.image_angle_a_rad),
                                             error(c.angle_b_rad, t.image_angle_b_rad)) < 0.1 ||
                                    std::max(error(c.angle_a_rad, t.image_angle_b_rad),
                                             error(c.angle_b_rad, t.image_angle_a_rad)) < 0.1;
                           });
    }
  }
  INFO("doors seen whole from the side: " << found << " / " << doors << " have a candidate");
  REQUIRE(doors >= 10);
  CHECK(found >= 0.8 * doors);
}

}  // namespace
}  // namespace corridorsim
