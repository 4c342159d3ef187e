#include "slam/features/harris_corners.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "slam/features/image_conversion.h"

namespace corridorsim::slam {

std::optional<OptionsProblem> HarrisCornerOptions::Check() const {
  return CheckOptionBounds(HarrisCornerOptionsTable(), *this);
}

std::optional<double> MedianDepth3x3(const ImageF& depth_m, int x, int y) {
  float values[9];
  int n = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const int u = x + dx, v = y + dy;
      if (u < 0 || v < 0 || u >= depth_m.width || v >= depth_m.height) continue;
      const float d = depth_m.at(u, v);
      if (!(std::isfinite(d) && d > 0.0f)) continue;
      // Insertion into the sorted prefix (at most nine values).
      int i = n++;
      for (; i > 0 && values[i - 1] > d; --i) values[i] = values[i - 1];
      values[i] = d;
    }
  }
  if (n == 0) return std::nullopt;
  return n % 2 == 1 ? static_cast<double>(values[n / 2])
                    : 0.5 * (static_cast<double>(values[n / 2 - 1]) + values[n / 2]);
}

std::vector<HarrisCorner> DetectHarrisCorners(const Image8& image, const ImageF* depth_m,
                                              const HarrisCornerOptions& options) {
  CheckOrDie(!options.Check(), "slam::DetectHarrisCorners", "the options fail their Check()");
  CheckOrDie(!depth_m || (depth_m->width == image.width && depth_m->height == image.height),
             "slam::DetectHarrisCorners", "the depth image's size differs from the image's");
  std::vector<HarrisCorner> corners;
  if (image.width < options.block_size_px || image.height < options.block_size_px) return corners;

  // The Harris response det(M) - k trace(M)^2 of the structure tensor M summed over the block,
  // from the 3x3 Sobel of the grey image as floats in [0, 255].
  cv::Mat grey_float;
  GreyMat(image).convertTo(grey_float, CV_32F);
  cv::Mat response;
  cv::cornerHarris(grey_float, response, options.block_size_px, 3, options.harris_k,
                   cv::BORDER_REFLECT_101);

  // goodFeaturesToTrack's selection: local maxima of the response (3x3) above quality_level of
  // the largest, strongest first, each kept unless a stronger kept one lies within
  // min_distance_px.
  double best = 0.0;
  cv::minMaxLoc(response, nullptr, &best);
  if (!(best > 0.0)) return corners;
  const float threshold = static_cast<float>(options.quality_level * best);
  cv::Mat dilated;
  cv::dilate(response, dilated, cv::Mat());
  struct Candidate {
    float response;
    int x, y;
  };
  std::vector<Candidate> candidates;
  // The border rows and columns are skipped as goodFeaturesToTrack does: their response sees
  // reflected pixels.
  for (int y = 1; y + 1 < response.rows; ++y) {
    const float* r = response.ptr<float>(y);
    const float* d = dilated.ptr<float>(y);
    for (int x = 1; x + 1 < response.cols; ++x) {
      if (r[x] >= threshold && r[x] == d[x]) candidates.push_back({r[x], x, y});
    }
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
    if (a.response != b.response) return a.response > b.response;
    return a.y != b.y ? a.y < b.y : a.x < b.x;
  });

  // Greedy spacing on a grid of min_distance_px cells: a candidate is compared with the kept
  // corners of its 3x3 cells only.
  const double min_d = options.min_distance_px;
  const double min_d2 = min_d * min_d;
  const int cell = std::max(1, static_cast<int>(std::ceil(min_d)));
  const int grid_w = (response.cols + cell - 1) / cell, grid_h = (response.rows + cell - 1) / cell;
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(grid_w) * grid_h);
  std::vector<Candidate> kept;
  for (const Candidate& c : candidates) {
    if (static_cast<int>(kept.size()) >= options.max_corners) break;
    const int gx = c.x / cell, gy = c.y / cell;
    bool far = true;
    for (int yy = std::max(0, gy - 1); far && yy <= std::min(grid_h - 1, gy + 1); ++yy) {
      for (int xx = std::max(0, gx - 1); far && xx <= std::min(grid_w - 1, gx + 1); ++xx) {
        for (int k : grid[static_cast<std::size_t>(yy) * grid_w + xx]) {
          const double dx = kept[k].x - c.x, dy = kept[k].y - c.y;
          if (dx * dx + dy * dy < min_d2) {
            far = false;
            break;
          }
        }
      }
    }
    if (!far) continue;
    grid[static_cast<std::size_t>(gy) * grid_w + gx].push_back(static_cast<int>(kept.size()));
    kept.push_back(c);
  }

  std::vector<cv::Point2f> points;
  for (const Candidate& c : kept)
    points.emplace_back(static_cast<float>(c.x), static_cast<float>(c.y));
  if (options.subpixel_half_window_px > 0 && !points.empty()) {
    const int w = options.subpixel_half_window_px;
    cv::cornerSubPix(grey_float, points, cv::Size(w, w), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.01));
  }
  corners.reserve(kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    HarrisCorner corner;
    corner.pixel_px = Eigen::Vector2d(points[i].x, points[i].y);
    // cornerSubPix moves a point by at most its window; keep it inside the image.
    corner.pixel_px.x() = std::clamp(corner.pixel_px.x(), 0.0, image.width - 1.0);
    corner.pixel_px.y() = std::clamp(corner.pixel_px.y(), 0.0, image.height - 1.0);
    corner.response = kept[i].response;
    if (depth_m) {
      corner.depth_m = MedianDepth3x3(*depth_m, static_cast<int>(std::lround(corner.pixel_px.x())),
                                      static_cast<int>(std::lround(corner.pixel_px.y())));
    }
    corners.push_back(corner);
  }
  return corners;
}

}  // namespace corridorsim::slam
