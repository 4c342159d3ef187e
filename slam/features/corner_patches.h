#pragma once
// Corners of an upward camera's image with the patches that identify them (P3: FAST corners;
// P2: Harris corners; both matched by their image patch, "NSSD" in P2's words, normalised
// cross-correlation here). A pure function of the image and the options.
//
// Patches are sampled on a grid turned by an angle the caller gives: an upward camera turns its
// image about the principal point as the robot turns, so a pipeline that samples every patch
// turned by its heading estimate gets patches aligned with the world, which match again after a
// turn (ours; P3 matched axis-aligned patches between nearby frames).

#include <optional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "common/error.h"
#include "common/image.h"
#include "common/options_table.h"

namespace corridorsim::slam {

enum class CornerDetector { kFast, kHarris };

struct CornerPatchOptions {
  CornerDetector detector = CornerDetector::kFast;
  int fast_threshold = 20;       // FAST: intensity difference on the 16-pixel circle (grey levels)
  double harris_k = 0.04;        // Harris (DetectHarrisCorners): k of det(M) - k trace(M)^2
  double harris_quality = 0.01;  // Harris: a corner's response must reach this fraction of the best
  int max_corners = 60;          // strongest first
  double min_distance_px = 12.0;  // no two corners closer than this; the stronger one stays
  int patch_half_px = 5;          // patches are (2 h + 1)^2 samples
  // FAST: half side of cv::cornerSubPix's window that refines each kept corner (0 = the integer
  // pixel FAST reports). On P3's tiled ceilings FAST fires on the four tile corners around a
  // seam crossing, 3-4 px from its centre, a different one as the view changes; an 11 x 11
  // window takes in the whole crossing and moves the corner onto it (median error 0.15 px,
  // docs/p3.md). A 7 x 7 window stops at the tile corner as often as not.
  int fast_subpixel_half_px = 5;
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<CornerPatchOptions>& CornerPatchOptionsTable();

struct CornerWithResponse {
  Eigen::Vector2d pixel_px = Eigen::Vector2d::Zero();
  double response = 0.0;  // FAST score or Harris response (only ratios mean something)
};

/// Corners of `grey` (CV_8UC1), strongest first (ties: row, then column), at least
/// patch_half_px + 2 px from the border (so that a patch turned by any angle fits). Harris is
/// P1's detector (DetectHarrisCorners, sub-pixel), FAST OpenCV's (9/16, non-maximum suppression),
/// each kept corner refined by cv::cornerSubPix when fast_subpixel_half_px > 0 (a corner the
/// refinement moves out of the margin, or onto a stronger corner's place, is dropped).
std::vector<CornerWithResponse> DetectCorners(const cv::Mat& grey,
                                              const CornerPatchOptions& options);

/// The (2 h + 1)^2 bilinear samples of `grey` around `pixel` on a grid turned by `angle_rad`
/// (image x towards image y), minus their mean, divided by their norm: a unit vector, or nullopt
/// for a flat patch (norm below 1e-3 grey levels) or one that leaves the image.
std::optional<std::vector<float>> SamplePatch(const cv::Mat& grey, const Eigen::Vector2d& pixel,
                                              double angle_rad, int half_px);

/// Normalised cross-correlation of two patches from SamplePatch (their dot product), in [-1, 1].
double PatchCorrelation(const std::vector<float>& a, const std::vector<float>& b);

}  // namespace corridorsim::slam
