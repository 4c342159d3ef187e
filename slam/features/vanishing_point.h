#pragma once
// The vanishing point of a corridor image (P1 section 2, eqs. 1-4, Fig. 3): Canny edges, Hough
// lines, rejection of lines nearly parallel to the image axes, and the least-squares
// intersection of the rest through the pseudo-inverse. A pure function of the image and its
// options: no state, no randomness (OpenCV's HoughLinesP seeds its own generator per call).

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/enum_names.h"
#include "common/error.h"
#include "common/image.h"
#include "common/options_table.h"

namespace corridorsim::slam {

/// Which Hough transform proposes the candidate lines.
enum class HoughMethod {
  kProbabilistic,  // cv::HoughLinesP: segments with endpoints (the default; docs/detectors.md)
  kStandard,       // cv::HoughLines: infinite lines (rho, theta), clipped to the image
};
inline constexpr EnumName<HoughMethod> kHoughMethodNames[] = {
    {HoughMethod::kProbabilistic, "probabilistic"}, {HoughMethod::kStandard, "standard"}};
std::string HoughMethodName(HoughMethod method);

/// The detector's options (defaults measured on rendered 640x480 corridor frames,
/// docs/detectors.md).
struct VanishingPointOptions {
  // Gaussian smoothing before Canny (px, standard deviation; 0 = none): rendered and real frames
  // carry sensor noise that would otherwise break edges into short pieces.
  double blur_sigma_px = 1.0;
  // Canny hysteresis thresholds on the L2 gradient magnitude of the 3x3 Sobel (grey levels per px).
  double canny_low = 20.0;
  double canny_high = 60.0;
  HoughMethod hough = HoughMethod::kProbabilistic;
  double hough_rho_px = 1.0;         // distance resolution of the accumulator (px)
  double hough_theta_deg = 1.0;      // angle resolution of the accumulator (deg)
  int hough_votes = 40;              // accumulator threshold (edge pixels on a line)
  double min_line_length_px = 40.0;  // probabilistic: shortest segment kept (px)
  double max_line_gap_px = 4.0;      // probabilistic: largest gap bridged within a segment (px)
  // Segments on one image line (an edge broken into pieces) are merged into one line: within
  // this angle of a longer segment (deg) and with both ends within this distance of its line (px).
  double merge_angle_deg = 1.0;
  double merge_distance_px = 3.0;
  // Each line is re-fitted (total least squares) to the Canny edge pixels within this distance
  // of it (px; 0 = keep the Hough transform's line): Hough lines are quantised to whole pixels
  // and to the accumulator's grid.
  double refine_band_px = 1.5;
  // P1 section 2: lines within this angle of the image's u or v axis do not converge to the
  // vanishing point (verticals of doors, horizontals of cross seams) and are rejected (deg).
  double axis_reject_deg = 8.0;
  // At most this many lines (the longest or strongest) enter the solve; the consensus seed
  // costs O(max_lines^3).
  int max_lines = 100;
  int min_lines = 4;  // fewer lines agreeing on the point: no point
  // Fewer distinct directions (merge_angle_deg apart) among them: no point. Two edges of one thin
  // line are two lines of one direction, and two directions always meet somewhere.
  int min_directions = 3;
  // Beyond P1: eq. 4 weighted by each line's precision at the point (the variance of its edge
  // fit's offset there, which grows with the distance from the fitted pixels and shrinks with
  // their number and spread), iterated from P1's unweighted solution. Long lines near the point
  // then outweigh short texture edges far from it, whose small slope errors P1's equal weights
  // turn into pixels at the point. false: P1's eq. 4 with equal weights.
  bool weighted = true;
  // The consensus and outlier pass (beyond P1): a line farther than this from the point (px),
  // or a segment the point falls inside, disagrees with it.
  double outlier_distance_px = 6.0;
  // No point when the kept lines' RMS distance to it exceeds this (px).
  double max_rms_residual_px = 3.0;
  // No point when the lines' directions are this close to parallel: the RMS angle of their
  // normals about the mean normal (deg); their intersection is then ill-conditioned.
  double min_direction_spread_deg = 4.0;
  // No point farther than this outside the image rectangle (px).
  double max_outside_image_px = 320.0;

  std::optional<OptionsProblem> Check() const;
};
/// The keys of the detector's options (the harness and docs/detectors.md list them).
const OptionTable<VanishingPointOptions>& VanishingPointOptionsTable();

/// An image line through two endpoints (px, OpenCV pixel coordinates: (0, 0) is the centre of
/// the top-left pixel).
struct ImageLineSegment {
  Eigen::Vector2d a_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d b_px = Eigen::Vector2d::Zero();
  // Edge pixels the line was fitted to (RefineToEdges); 0 when not fitted (its length stands in).
  int support_px = 0;
};

/// Why a frame gave no vanishing point, or kFound.
enum class VanishingPointStatus {
  kFound,
  kTooFewLines,     // fewer than min_lines after the axis rejection (a black frame, a wall seen
                    // head-on, a frame of horizontals and verticals)
  kIllConditioned,  // the lines are nearly parallel (min_direction_spread_deg)
  kNotConverging,   // fewer than min_lines agree on one point, or their RMS residual is too large
  kOutsideImage,    // the point lies beyond max_outside_image_px
};
std::string VanishingPointStatusName(VanishingPointStatus status);

struct VanishingPointQuality {
  double rms_residual_px = 0.0;    // RMS distance of the used lines to the point (px; weighted)
  int line_count = 0;              // lines used in the final solve
  int candidate_count = 0;         // lines the Hough transform proposed (before max_lines)
  int rejected_axis_count = 0;     // rejected as nearly parallel to an image axis (P1 section 2)
  int merged_count = 0;            // merged into a longer segment on the same image line
  int direction_count = 0;         // distinct directions among the used lines
  int rejected_outlier_count = 0;  // candidate lines that disagree with the point (consensus and
                                   // outlier pass)
};

struct VanishingPoint {
  Eigen::Vector2d pixel_px = Eigen::Vector2d::Zero();  // (u, v) of P1 eq. 4 (px)
  std::vector<ImageLineSegment> lines;                 // the lines of the final solve
  VanishingPointQuality quality;
};

/// What a detection found, with or without a point: the status and the counts always, the lines
/// that passed the axis rejection (for overlays and diagnosis).
struct VanishingPointReport {
  VanishingPointStatus status = VanishingPointStatus::kTooFewLines;
  VanishingPointQuality quality;  // of the last solve (line_count 0 when none was made)
  // The lines after the axis rejection, the merging of collinear pieces and max_lines.
  std::vector<ImageLineSegment> candidate_lines;
};

/// The vanishing point of `image` (RGB, RGBA or grey; any size), or none when the evidence is
/// poor (the report says why). `options` must pass Check() (aborts otherwise: a bug).
std::optional<VanishingPoint> DetectVanishingPoint(const Image8& image,
                                                   const VanishingPointOptions& options,
                                                   VanishingPointReport* report = nullptr);

/// The least-squares intersection of `lines` (P1 eqs. 1-4): each line as a_i u + b_i v = c_i
/// with (a_i, b_i) its unit normal, so the residual a_i u + b_i v - c_i is the point's distance
/// to it in px; u = A^+ c with A^+ = (A^T A)^-1 A^T. With `weights` (one per line, positive),
/// the weighted form u = (A^T W A)^-1 A^T W c. None when fewer than two lines or the normal
/// matrix is singular. `residuals_px` (optional) gets the signed distance of each line.
std::optional<Eigen::Vector2d> IntersectLines(const std::vector<ImageLineSegment>& lines,
                                              std::vector<double>* residuals_px = nullptr,
                                              const std::vector<double>* weights = nullptr);

/// The variance of a fitted line's offset at `point`, in units of the edge pixels' own variance
/// across the line: 1/n + 12 D^2 / (n L^2) for n pixels spread evenly over the length L, D the
/// distance along the line from the segment's middle to the point's foot (a total least squares
/// fit's offset and slope errors). n is the line's support_px, or its length when not fitted.
double LineOffsetVariance(const ImageLineSegment& line, const Eigen::Vector2d& point);

}  // namespace corridorsim::slam
