#include "slam/features/corner_patches.h"

#include <algorithm>
#include <cmath>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "slam/features/harris_corners.h"
#include "slam/features/image_conversion.h"

namespace corridorsim::slam {

std::optional<OptionsProblem> CornerPatchOptions::Check() const {
  return CheckOptionBounds(CornerPatchOptionsTable(), *this);
}

std::vector<CornerWithResponse> DetectCorners(const cv::Mat& grey, const CornerPatchOptions& o) {
  CheckOrDie(grey.type() == CV_8UC1, "slam::DetectCorners", "expected a grey CV_8UC1 image");
  CheckOrDie(!o.Check(), "slam::DetectCorners", "the options fail their Check()");
  std::vector<CornerWithResponse> all;
  const int margin = o.patch_half_px + 2;
  const auto inside = [&](double x, double y) {
    return x >= margin && y >= margin && x < grey.cols - margin && y < grey.rows - margin;
  };
  if (o.detector == CornerDetector::kFast) {
    std::vector<cv::KeyPoint> keypoints;
    cv::FAST(grey, keypoints, o.fast_threshold, true, cv::FastFeatureDetector::TYPE_9_16);
    for (const cv::KeyPoint& k : keypoints) {
      if (inside(k.pt.x, k.pt.y)) all.push_back({{k.pt.x, k.pt.y}, k.response});
    }
  } else {
    // P2's Harris corners are P1's detector (harris_corners.h): its selection already spaces and
    // orders them; only the patch margin is applied here.
    HarrisCornerOptions harris;
    harris.max_corners = o.max_corners;
    harris.quality_level = o.harris_quality;
    harris.min_distance_px = o.min_distance_px;
    harris.harris_k = o.harris_k;
    std::vector<CornerWithResponse> kept;
    for (const HarrisCorner& c : DetectHarrisCorners(ImageFromMat(grey), nullptr, harris)) {
      if (inside(c.pixel_px.x(), c.pixel_px.y())) kept.push_back({c.pixel_px, c.response});
    }
    return kept;
  }
  // Strongest first, ties in raster order; then greedy spacing.
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    if (a.response != b.response) return a.response > b.response;
    if (a.pixel_px.y() != b.pixel_px.y()) return a.pixel_px.y() < b.pixel_px.y();
    return a.pixel_px.x() < b.pixel_px.x();
  });
  std::vector<CornerWithResponse> kept;
  const double min2 = o.min_distance_px * o.min_distance_px;
  for (const CornerWithResponse& c : all) {
    if (int(kept.size()) >= o.max_corners) break;
    const bool crowded = std::any_of(kept.begin(), kept.end(), [&](const CornerWithResponse& k) {
      return (k.pixel_px - c.pixel_px).squaredNorm() < min2;
    });
    if (!crowded) kept.push_back(c);
  }
  if (o.fast_subpixel_half_px <= 0 || kept.empty()) return kept;
  std::vector<cv::Point2f> points;
  points.reserve(kept.size());
  for (const CornerWithResponse& c : kept)
    points.emplace_back(float(c.pixel_px.x()), float(c.pixel_px.y()));
  const int w = o.fast_subpixel_half_px;
  cv::cornerSubPix(grey, points, cv::Size(w, w), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.01));
  std::vector<CornerWithResponse> refined;
  refined.reserve(kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const double x = points[i].x, y = points[i].y;
    if (!std::isfinite(x) || !std::isfinite(y) || !inside(x, y)) continue;
    const Eigen::Vector2d pixel(x, y);
    // Two corners of one crossing that the refinement brought together stay one corner.
    const bool taken = std::any_of(refined.begin(), refined.end(), [&](const auto& k) {
      return (k.pixel_px - pixel).squaredNorm() < 0.25 * min2;
    });
    if (!taken) refined.push_back({pixel, kept[i].response});
  }
  return refined;
}

std::optional<std::vector<float>> SamplePatch(const cv::Mat& grey, const Eigen::Vector2d& pixel,
                                              double angle_rad, int half_px) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  const int side = 2 * half_px + 1;
  std::vector<float> patch(std::size_t(side * side));
  double sum = 0.0;
  for (int j = -half_px; j <= half_px; ++j) {
    for (int i = -half_px; i <= half_px; ++i) {
      const double x = pixel.x() + c * i - s * j, y = pixel.y() + s * i + c * j;
      const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
      if (x0 < 0 || y0 < 0 || x0 + 1 >= grey.cols || y0 + 1 >= grey.rows) return std::nullopt;
      const double fx = x - x0, fy = y - y0;
      const std::uint8_t* r0 = grey.ptr<std::uint8_t>(y0);
      const std::uint8_t* r1 = grey.ptr<std::uint8_t>(y0 + 1);
      const double v = (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) +
                       fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
      patch[std::size_t((j + half_px) * side + i + half_px)] = float(v);
      sum += v;
    }
  }
  const double mean = sum / double(patch.size());
  double norm2 = 0.0;
  for (float& v : patch) {
    v = float(v - mean);
    norm2 += double(v) * v;
  }
  if (!(std::sqrt(norm2) > 1e-3)) return std::nullopt;
  const double inv = 1.0 / std::sqrt(norm2);
  for (float& v : patch) v = float(v * inv);
  return patch;
}

double PatchCorrelation(const std::vector<float>& a, const std::vector<float>& b) {
  CheckOrDie(a.size() == b.size(), "slam::PatchCorrelation", "patches of different sizes");
  double dot = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) dot += double(a[i]) * b[i];
  return std::clamp(dot, -1.0, 1.0);
}

}  // namespace corridorsim::slam
