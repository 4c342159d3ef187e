#pragma once
// Harris corners with the registered depth at each (P1 section 6: the corner-based EKF SLAM
// baseline P1 compares against uses Harris corners). A pure function of the image, the optional
// depth image and the options.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/error.h"
#include "common/image.h"
#include "common/options_table.h"

namespace corridorsim::slam {

/// The detector's options (cv::cornerHarris, then goodFeaturesToTrack's selection).
struct HarrisCornerOptions {
  int max_corners = 300;          // at most this many corners, strongest first
  double quality_level = 0.01;    // a corner's response must reach this fraction of the best one
  double min_distance_px = 10.0;  // no two corners closer than this (px); the stronger one stays
  int block_size_px = 3;          // side of the window the structure tensor sums over (px)
  double harris_k = 0.04;         // k of the Harris response det(M) - k trace(M)^2
  // Refine each corner to sub-pixel position (cv::cornerSubPix over a window of this half-size,
  // px; 0 = the integer pixel of the response's maximum).
  int subpixel_half_window_px = 3;

  std::optional<OptionsProblem> Check() const;
};
/// The keys of the detector's options (the harness and docs/detectors.md list them).
const OptionTable<HarrisCornerOptions>& HarrisCornerOptionsTable();

struct HarrisCorner {
  Eigen::Vector2d pixel_px = Eigen::Vector2d::Zero();  // OpenCV pixel coordinates (px)
  // Median of the valid (> 0, finite) depths of the 3x3 window around the corner's pixel in the
  // registered depth image (m); none without a depth image or a valid depth in the window.
  std::optional<double> depth_m;
  // cv::cornerHarris' response at the corner's pixel (the grey image as floats in [0, 255]; only
  // its ratios to other responses mean something).
  double response = 0.0;
};

/// Harris corners of `image` (RGB, RGBA or grey), strongest first (ties: row, then column).
/// `depth_m` (optional) is the depth image registered to `image` (metres, 0 = invalid): it must
/// have the image's size (aborts otherwise: the caller checks its input). `options` must pass
/// Check() (aborts otherwise).
std::vector<HarrisCorner> DetectHarrisCorners(const Image8& image, const ImageF* depth_m,
                                              const HarrisCornerOptions& options);

/// The median of the valid depths (> 0 and finite) in the 3x3 window centred on (x, y), clipped
/// to the image; none when the window holds none. An even count gives the mean of the middle two.
std::optional<double> MedianDepth3x3(const ImageF& depth_m, int x, int y);

}  // namespace corridorsim::slam
