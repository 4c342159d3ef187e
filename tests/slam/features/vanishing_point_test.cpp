// Tests slam/features/vanishing_point.cpp: P1 eqs. 1-4 on exact lines, the detector on synthetic
// corridors drawn with OpenCV (a known vanishing point), and no point where the evidence is poor.
#include "slam/features/vanishing_point.h"

#include <cmath>
#include <numbers>
#include <vector>

#include <Eigen/Geometry>
#include <catch2/catch.hpp>
#include <opencv2/imgproc.hpp>

#include "slam/features/image_conversion.h"
#include "tests/support/feature_tolerances.h"
#include "tests/support/synthetic_corridor.h"

namespace corridorsim::slam {
namespace {

constexpr int kWidth = test::kCorridorImageWidth;
constexpr int kHeight = test::kCorridorImageHeight;
constexpr double kDeg = std::numbers::pi / 180.0;
using test::CorridorView;
using test::DrawCorridor;

double Distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return (a - b).norm(); }

TEST_CASE("IntersectLines solves P1 eq. 4 exactly for lines through one point",
          "[slam][features]") {
  const Eigen::Vector2d point(123.25, -40.5);
  std::vector<ImageLineSegment> lines;
  for (double angle_deg : {10.0, 35.0, 80.0, 120.0, 170.0}) {
    const Eigen::Vector2d d(std::cos(angle_deg * kDeg), std::sin(angle_deg * kDeg));
    lines.push_back({point + 50.0 * d, point + 300.0 * d});
  }
  std::vector<double> residuals;
  const auto u = IntersectLines(lines, &residuals);
  REQUIRE(u);
  CHECK(Distance(*u, point) < test::kLineIntersectionPx);
  REQUIRE(residuals.size() == lines.size());
  for (double r : residuals) CHECK(std::abs(r) < test::kLineIntersectionPx);

  // The residual is the signed distance in px: a line moved 3 px along its normal reads 3.
  const Eigen::Vector2d d = (lines[0].b_px - lines[0].a_px).normalized();
  const Eigen::Vector2d normal(-d.y(), d.x());
  std::vector<ImageLineSegment> moved = lines;
  moved[0] = {lines[0].a_px + 3.0 * normal, lines[0].b_px + 3.0 * normal};
  moved.resize(2);
  REQUIRE(IntersectLines(moved, &residuals));
  CHECK(std::abs(residuals[0]) < test::kLineIntersectionPx);  // two lines meet exactly

  // Parallel lines, one line or a degenerate segment: no point.
  CHECK_FALSE(IntersectLines({{{0, 0}, {10, 10}}, {{0, 5}, {10, 15}}}));
  CHECK_FALSE(IntersectLines({{{0, 0}, {10, 10}}}));
  CHECK_FALSE(IntersectLines({{{0, 0}, {10, 10}}, {{3, 3}, {3, 3}}}));
}

TEST_CASE("the vanishing point of a synthetic corridor is found within 1.5 px",
          "[slam][features]") {
  const VanishingPointOptions options;
  for (const auto& [yaw_deg, pitch_deg, y_m] :
       {std::tuple{4.0, -2.0, 0.3}, std::tuple{0.0, 0.0, 0.0}, std::tuple{-9.0, 3.0, -0.5},
        std::tuple{15.0, -4.0, 0.6}}) {
    CorridorView view;
    view.yaw_rad = yaw_deg * kDeg;
    view.pitch_rad = pitch_deg * kDeg;
    view.camera_in_world.y() = y_m;
    const Eigen::Vector2d truth = view.VanishingPoint();
    INFO("yaw " << yaw_deg << " deg, pitch " << pitch_deg << " deg, y " << y_m << " m, truth ("
                << truth.x() << ", " << truth.y() << ")");
    VanishingPointReport report;
    const auto vp = DetectVanishingPoint(DrawCorridor(view), options, &report);
    INFO("status " << VanishingPointStatusName(report.status) << ", lines "
                   << report.quality.line_count << " of " << report.quality.candidate_count);
    REQUIRE(vp);
    CHECK(report.status == VanishingPointStatus::kFound);
    CHECK(Distance(vp->pixel_px, truth) < test::kSyntheticVanishingPointPx);
    CHECK(vp->quality.line_count >= options.min_lines);
    CHECK(vp->lines.size() == static_cast<std::size_t>(vp->quality.line_count));
    CHECK(vp->quality.rms_residual_px <= options.max_rms_residual_px);
    CHECK(vp->quality.rejected_axis_count > 0);  // the doors' verticals at least
    CHECK(vp->quality.candidate_count >= vp->quality.line_count + vp->quality.rejected_axis_count);
  }
}

TEST_CASE("both Hough transforms find the synthetic corridor's vanishing point",
          "[slam][features]") {
  const CorridorView view;
  const Image8 image = DrawCorridor(view);
  VanishingPointOptions options;
  options.hough = HoughMethod::kStandard;
  options.hough_votes = 120;
  const auto vp = DetectVanishingPoint(image, options);
  REQUIRE(vp);
  CHECK(Distance(vp->pixel_px, view.VanishingPoint()) < test::kSyntheticVanishingPointPx);
}

TEST_CASE("the detector is deterministic", "[slam][features]") {
  const Image8 image = DrawCorridor(CorridorView{});
  const auto a = DetectVanishingPoint(image, VanishingPointOptions{});
  const auto b = DetectVanishingPoint(image, VanishingPointOptions{});
  REQUIRE(a);
  REQUIRE(b);
  CHECK(a->pixel_px == b->pixel_px);
  REQUIRE(a->lines.size() == b->lines.size());
  for (std::size_t i = 0; i < a->lines.size(); ++i) {
    CHECK(a->lines[i].a_px == b->lines[i].a_px);
    CHECK(a->lines[i].b_px == b->lines[i].b_px);
  }
}

TEST_CASE("a black frame has no vanishing point", "[slam][features]") {
  VanishingPointReport report;
  CHECK_FALSE(DetectVanishingPoint(Image8(kWidth, kHeight, 3), VanishingPointOptions{}, &report));
  CHECK(report.status == VanishingPointStatus::kTooFewLines);
  CHECK(report.quality.candidate_count == 0);
  CHECK_FALSE(DetectVanishingPoint(Image8(0, 0, 3), VanishingPointOptions{}));
}

TEST_CASE("a frame of horizontal and vertical lines only has no vanishing point",
          "[slam][features]") {
  cv::Mat image(kHeight, kWidth, CV_8UC3, cv::Scalar(128, 128, 128));
  for (int k = 0; k < 8; ++k) {
    cv::line(image, {40 + 70 * k, 20}, {40 + 70 * k + 1, 460}, cv::Scalar(20, 20, 20), 3);
    cv::line(image, {10, 30 + 55 * k}, {630, 30 + 55 * k - 2}, cv::Scalar(240, 240, 240), 3);
  }
  VanishingPointReport report;
  CHECK_FALSE(DetectVanishingPoint(ImageFromMat(image), VanishingPointOptions{}, &report));
  CHECK(report.status == VanishingPointStatus::kTooFewLines);
  CHECK(report.quality.rejected_axis_count >= 16);
}

TEST_CASE("a wall seen head-on has no vanishing point", "[slam][features]") {
  // Wall, floor and ceiling bands, doors with frames, door plates with room numbers, a poster.
  cv::Mat image(kHeight, kWidth, CV_8UC3, cv::Scalar(170, 175, 180));
  cv::rectangle(image, {0, 0}, {639, 60}, cv::Scalar(225, 225, 225), cv::FILLED);
  cv::rectangle(image, {0, 400}, {639, 479}, cv::Scalar(70, 80, 90), cv::FILLED);
  for (int x : {60, 380}) {
    cv::rectangle(image, {x - 8, 130}, {x + 168, 400}, cv::Scalar(60, 50, 40), cv::FILLED);
    cv::rectangle(image, {x, 138}, {x + 160, 400}, cv::Scalar(120, 90, 60), cv::FILLED);
    cv::circle(image, {x + 140, 280}, 6, cv::Scalar(200, 200, 200), cv::FILLED, cv::LINE_AA);
    cv::rectangle(image, {x + 185, 200}, {x + 245, 232}, cv::Scalar(250, 250, 250), cv::FILLED);
    cv::putText(image, x == 60 ? "101" : "103", {x + 190, 226}, cv::FONT_HERSHEY_SIMPLEX, 0.8,
                cv::Scalar(10, 10, 10), 2, cv::LINE_AA);
  }
  cv::rectangle(image, {280, 150}, {340, 230}, cv::Scalar(40, 120, 200), cv::FILLED);
  VanishingPointReport report;
  CHECK_FALSE(DetectVanishingPoint(ImageFromMat(image), VanishingPointOptions{}, &report));
  CHECK(report.status == VanishingPointStatus::kTooFewLines);
}

TEST_CASE("lines that do not meet in one point give no vanishing point", "[slam][features]") {
  // Tangents of a circle: every line is 150 px from the centre, no point is near them all.
  cv::Mat image(kHeight, kWidth, CV_8UC3, cv::Scalar(0, 0, 0));
  const Eigen::Vector2d centre(320, 240);
  for (int k = 0; k < 12; ++k) {
    const double a = (15.0 + 30.0 * k) * kDeg;
    const Eigen::Vector2d n(std::cos(a), std::sin(a)), d(-std::sin(a), std::cos(a));
    const Eigen::Vector2d p = centre + 150.0 * n - 120.0 * d, q = centre + 150.0 * n + 120.0 * d;
    cv::line(image, cv::Point(static_cast<int>(p.x()), static_cast<int>(p.y())),
             cv::Point(static_cast<int>(q.x()), static_cast<int>(q.y())), cv::Scalar(255, 255, 255),
             2, cv::LINE_AA);
  }
  VanishingPointReport report;
  CHECK_FALSE(DetectVanishingPoint(ImageFromMat(image), VanishingPointOptions{}, &report));
  CHECK(report.status == VanishingPointStatus::kNotConverging);
}

TEST_CASE("nearly parallel lines and a point far outside the image give no vanishing point",
          "[slam][features]") {
  cv::Mat parallel(kHeight, kWidth, CV_8UC3, cv::Scalar(0, 0, 0));
  for (int k = 0; k < 8; ++k) {
    cv::line(parallel, {40 + 60 * k, 40}, {40 + 60 * k + 200, 440}, cv::Scalar(255, 255, 255), 2,
             cv::LINE_AA);
  }
  VanishingPointReport report;
  CHECK_FALSE(DetectVanishingPoint(ImageFromMat(parallel), VanishingPointOptions{}, &report));
  CHECK(report.status == VanishingPointStatus::kIllConditioned);

  // A corridor looked at 40 degrees off its axis: its lines meet ~480 px right of the image.
  CorridorView view;
  view.yaw_rad = 40.0 * kDeg;
  view.camera_in_world.y() = -0.6;
  REQUIRE(view.VanishingPoint().x() > kWidth + 100.0);
  VanishingPointOptions options;
  options.max_outside_image_px = 100.0;
  const auto vp = DetectVanishingPoint(DrawCorridor(view), options, &report);
  CHECK_FALSE(vp);
  CHECK(report.status == VanishingPointStatus::kOutsideImage);
}

TEST_CASE("vanishing point options: defaults pass, bounds and relations are checked",
          "[slam][features]") {
  CHECK_FALSE(VanishingPointOptions{}.Check());
  VanishingPointOptions o;
  o.canny_high = o.canny_low - 1;
  REQUIRE(o.Check());
  CHECK(o.Check()->key == "canny_high");
  o = VanishingPointOptions{};
  o.min_lines = o.max_lines + 1;
  REQUIRE(o.Check());
  CHECK(o.Check()->key == "min_lines");
  o = VanishingPointOptions{};
  o.axis_reject_deg = 45.0;  // would reject every line
  REQUIRE(o.Check());
  CHECK(o.Check()->key == "axis_reject_deg");
  o = VanishingPointOptions{};
  o.hough_votes = 0;
  CHECK(o.Check()->key == "hough_votes");
  CHECK(HoughMethodName(HoughMethod::kStandard) == "standard");
  CHECK(VanishingPointStatusName(VanishingPointStatus::kOutsideImage) == "outside_image");
}

TEST_CASE("LineOffsetVariance grows with the distance from the fitted pixels", "[slam][features]") {
  // 101 pixels over 100 px: at the middle only the offset error (1/n), 50 px beyond an end the
  // slope error too: 1/n + 12 D^2 / (n L^2) with D = 100.
  ImageLineSegment line{{0, 0}, {100, 0}, 101};
  CHECK(LineOffsetVariance(line, {50, 7}) == Approx(1.0 / 101));
  CHECK(LineOffsetVariance(line, {150, 0}) ==
        Approx(1.0 / 101 + 12.0 * 100 * 100 / (101.0 * 100 * 100)));
  // Not fitted: its length stands in for the pixel count.
  line.support_px = 0;
  CHECK(LineOffsetVariance(line, {50, 0}) == Approx(1.0 / 100));
}

TEST_CASE(
    "weighted IntersectLines follows the weights; the detector's weighting trusts long "
    "lines near the point over short ones far from it",
    "[slam][features]") {
  // Two exact lines through (0, 0) and one that misses it by 2 px.
  const std::vector<ImageLineSegment> lines = {
      {{10, 10}, {200, 200}, 190}, {{-10, 10}, {-200, 200}, 190}, {{-300, 2}, {-250, 52}, 50}};
  std::vector<double> residuals;
  const auto equal = IntersectLines(lines, &residuals);
  REQUIRE(equal);
  CHECK(equal->norm() > 0.3);  // P1's equal weights: pulled by the third line
  const std::vector<double> weights = {1.0, 1.0, 1e-6};
  const auto weighted = IntersectLines(lines, &residuals, &weights);
  REQUIRE(weighted);
  CHECK(weighted->norm() < 0.01);
  // The detector's weights: the third line's slope, fitted over 50 px, is worth little 275 px
  // from its middle.
  const double far = LineOffsetVariance(lines[2], Eigen::Vector2d::Zero());
  const double near = LineOffsetVariance(lines[0], Eigen::Vector2d::Zero());
  CHECK(far > 50 * near);
  // A weight that is not positive and finite: no point (a bug upstream, not a guess).
  const std::vector<double> bad = {1.0, 0.0, 1.0};
  CHECK_FALSE(IntersectLines(lines, &residuals, &bad));
}

}  // namespace
}  // namespace corridorsim::slam
