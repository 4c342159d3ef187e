#pragma once
// P1 section 3.1: door-plate detection in a lateral camera image. Candidates come from the
// vertical edges of the digits (Sobel in x, threshold, morphological closing that merges a
// number's digits into one blob, external contours, size and aspect filter), at a few image
// scales so that near and far plates both give digit-sized blobs; each candidate is then scored
// by a linear SVM on its patch (P1 eqs. 5-6). Pure functions of an image: no state, no I/O.
//
// Boxes are in the image's pixels with (0, 0) the centre of the top-left pixel (as
// render::PlateTruth): a blob covering pixel columns x0..x1 spans [x0 - 0.5, x1 + 0.5].

#include <optional>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include "common/error.h"
#include "common/image.h"
#include "common/options_table.h"

namespace corridorsim::slam {

/// An axis-aligned box in image pixels (pixel-centre convention above); min < max.
struct BoxPx {
  double min_x = 0.0, min_y = 0.0, max_x = 0.0, max_y = 0.0;
  double width() const { return max_x - min_x; }
  double height() const { return max_y - min_y; }
};
/// Intersection over union of two boxes (0 when either is empty).
double IntersectionOverUnion(const BoxPx& a, const BoxPx& b);

struct DoorPlateDetectorOptions {
  // Candidate segmentation, in the pixels of each scaled image.
  // Image scales searched (each in (0, 1]): a step of 1/sqrt(2), so that at one of them the
  // closing kernel is wider than the gaps between digits (~0.25 digit heights) and narrower than
  // the gap to the plate's edge (~0.5-1 digit heights).
  std::vector<double> scales{1.0, 0.71, 0.5, 0.35, 0.25, 0.18};
  double edge_threshold = 80.0;  // |Sobel x| (3x3, grey levels x 4) that counts as an edge
  int close_width_px = 3;        // closing kernel: merges a number's digits horizontally
  int close_height_px = 3;
  int min_height_px = 8;  // blob size bounds at each scale
  int max_height_px = 22;
  int min_width_px = 6;
  int max_width_px = 200;
  double min_aspect = 0.9;  // blob width / height
  double max_aspect = 6.0;
  double min_edge_fill = 0.15;  // fraction of edge pixels inside the blob's box
  int max_candidates = 600;     // per image, after merging duplicates across scales
  // Segmentation: candidates overlapping more than this are one (the finest scale's kept).
  double duplicate_iou = 0.85;
  // Detection: of scored candidates overlapping more than this, the highest score is kept.
  double suppression_iou = 0.3;
  // P1 eq. 5 feature vector: the patch (box grown by context on every side) resized.
  int patch_width_px = 60;
  int patch_height_px = 30;
  double context = 0.5;  // fraction of the box's width / height added on each side
  // Histogram of oriented gradients of the patch appended to its pixels (ours, not P1's): cell
  // side in patch pixels, 0 = pixels only (P1's feature). Blocks of 2 x 2 cells, a cell apart,
  // 9 unsigned orientation bins (cv::HOGDescriptor). Chosen on a validation set: docs/detectors.md.
  int hog_cell_px = 5;
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<DoorPlateDetectorOptions>& DoorPlateDetectorOptionsTable();

/// P1 section 3.1's segmentation: the candidate number regions of `image` (RGB or grey), in
/// image pixels, in a fixed order (scale, then contour order), duplicates across scales merged
/// (the first kept), at most options.max_candidates.
std::vector<BoxPx> SegmentPlateCandidates(const Image8& image,
                                          const DoorPlateDetectorOptions& options);

/// P1 eq. 5: the feature vector of `box` in `image`, a 1 x PlateFeatureCount CV_32F row: grey
/// patch (with context) resized (INTER_AREA), flipped to dark text on a light ground when its Otsu
/// minority class is the bright one, then scaled to zero mean and unit variance (the normalisation
/// is ours: it makes the score independent of plate colours and exposure); with hog_cell_px > 0,
/// followed by the patch's HOG descriptor (ours: digit strokes seen as gradients, not grey levels).
cv::Mat PlatePatchFeatures(const Image8& image, const BoxPx& box,
                           const DoorPlateDetectorOptions& options);

/// The length of PlatePatchFeatures' row for these options.
int PlateFeatureCount(const DoorPlateDetectorOptions& options);

/// P1 eq. 6: the SVM margin s(x) of a feature row; positive = door plate. `svm` is linear.
double PlateScore(const cv::ml::SVM& svm, const cv::Mat& features);

struct PlateCandidate {
  BoxPx box_px;        // the number region
  double score = 0.0;  // SVM margin s(x), positive = plate
};
/// Segmentation, then every candidate scored by `svm`, by decreasing score (ties in segmentation
/// order), none suppressed.
std::vector<PlateCandidate> ScorePlateCandidates(const Image8& image, const cv::ml::SVM& svm,
                                                 const DoorPlateDetectorOptions& options);
/// Non-maximum suppression: the indices of `boxes` (given in priority order) kept when each box
/// overlapping a kept one by IoU > max_iou is dropped, in that order.
std::vector<std::size_t> SuppressOverlapping(const std::vector<BoxPx>& boxes, double max_iou);

/// The grey (single-channel CV_8U) view of an RGB, RGBA or grey Image8, copied: the whole image,
/// or a region inside it (the same pixels as the whole image's grey cropped).
cv::Mat GreyImage(const Image8& image);
cv::Mat GreyImage(const Image8& image, const cv::Rect& region);

}  // namespace corridorsim::slam
