#pragma once
// P3 section II: circular ceiling lamps in an upward camera's image. The brightest parts of the
// image (a threshold) are grouped into regions (connected components); each region's edge points
// (Canny, kept where they outline the region) are tested for a circle by P3's random three-point
// method (eqs. 1-2): the perpendicular bisectors of two chords of three random edge points meet
// at the centre of the circle through them. A circle gives the same centre for every triple; a
// polygon (a panel lamp) does not. The region is a circular lamp when the standard deviations of
// the centres along their two principal axes, sigma1 and sigma2, are both below K_conv (the
// 2-sigma ellipse of the centres fits in a circle of radius 2 K_conv; P3 Fig. 1).
//
// Beyond P3, as the issue asks of a calibrated lens:
// - The test runs on the edge points mapped through the camera model onto the normalised image
//   plane (the bearing's x/z, y/z): a circle on a ceiling parallel to the image plane is a circle
//   there, whatever the lens. In a fisheye's pixels a lamp off the axis is an ellipse, and the
//   three-point centres of an ellipse spread. K_conv is given in pixels at the principal point
//   (divided by the focal length on the normalised plane). Without a model (nullptr) the pixels
//   are used as they are (P3's pinhole form).
// - P3 Fig. 3b: edge points on (within `border_margin_px` of) the image border are ignored, so a
//   lamp cut by the border still gives its true centre; the same holds where a lamp is cut by
//   the limit of the model's valid range.
// - A lamp mirrored in a wall strip (P3 Fig. 3c) is a bright circle like any other and is
//   detected as one; the SLAM treats it as a lamp behind the wall.
// A pure function of the image, the model and the options: the random triples come from a
// RandomStream seeded by `seed` and the region's bounding box, so that the same image gives the
// same lamps, in any order of the regions.

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/camera_models.h"
#include "common/error.h"
#include "common/image.h"
#include "common/options_table.h"

namespace corridorsim::slam {

struct CeilingLampOptions {
  int brightness_threshold = 235;  // grey level (0-255) above which a pixel is a brightest part
  int min_area_px = 40;            // regions smaller than this are noise
  int max_area_px = 60000;         // larger regions are not a lamp (a lit wall, a white frame)
  int max_regions = 64;            // regions tested per image, largest first (bounds the time)
  double canny_low = 60.0;         // Canny thresholds on the grey image (3x3 Sobel, L2)
  double canny_high = 150.0;
  // Grey-level step across a region's outline below which it is not a lamp (beyond P3): a lamp's
  // light ends sharply (85-110 levels in the shipped scenarios), the glare it throws on a wall
  // fades (12-16 levels where it crosses the threshold).
  double min_edge_contrast = 40.0;
  int border_margin_px = 2;  // edge points this close to the image border are ignored (Fig. 3b)
  int min_edge_points = 12;  // fewer usable edge points: no test (counted as rejected)
  int triples = 60;          // random three-point centres per region (P3: "several times")
  // Triples whose chords are shorter than this fraction of the region's edge-point spread are
  // drawn again (nearly coincident points make the bisectors ill-conditioned).
  double min_chord_fraction = 1.0;
  double k_conv_px = 3.0;  // K_conv: sigma1 and sigma2 of the centres below it = circular (px)
  std::uint64_t seed = 0;  // of the random triples
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<CeilingLampOptions>& CeilingLampOptionsTable();

/// One bright region and its circle test.
struct CeilingLampRegion {
  Eigen::Vector2d center_px = Eigen::Vector2d::Zero();  // the mean three-point centre (px)
  double radius_px = 0.0;      // mean distance of the used edge points from the centre (px)
  double sigma1_px = 0.0;      // standard deviations of the centres along their principal axes,
  double sigma2_px = 0.0;      // sigma1 >= sigma2, in px at the principal point
  int area_px = 0;             // pixels of the region
  int edge_points = 0;         // edge points used (border ones left out)
  double edge_contrast = 0.0;  // mean grey step across the outline (grey levels)
  bool cut_by_border = false;  // some edge points were left out at the border
  bool circular = false;       // sigma1 and sigma2 < K_conv: a circular lamp
  // Why a region is not a circular lamp: "" (it is), "low_contrast", "too_few_edge_points",
  // "not_circular".
  const char* rejection = "";
};

struct CeilingLampDetection {
  std::vector<CeilingLampRegion> lamps;     // circular lamps, largest region first
  std::vector<CeilingLampRegion> rejected;  // regions tested and rejected (panel lamps, ...)
  int regions = 0;          // bright regions within the area bounds (before max_regions)
  int regions_skipped = 0;  // beyond max_regions
};

/// P3 section II on `image` (RGB or grey); `model` (may be null) is the camera's calibrated model,
/// whose size must be the image's.
CeilingLampDetection DetectCeilingLamps(const Image8& image, const CameraModel* model,
                                        const CeilingLampOptions& options);

/// P3 eqs. 1-2: the intersection of the perpendicular bisectors of p1p2 and p2p3 (the centre of
/// the circle through the three points); nullopt when the points are (nearly) collinear.
std::optional<Eigen::Vector2d> ThreePointCentre(const Eigen::Vector2d& p1,
                                                const Eigen::Vector2d& p2,
                                                const Eigen::Vector2d& p3);

}  // namespace corridorsim::slam
