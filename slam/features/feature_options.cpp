// The scenario keys of the feature detectors (slam/features/): one table per options struct, with
// each key's unit, bounds and doc (common/options_table.h). The structs, their Check() and the
// detectors that read them stay in their own files; the tables sit together so that the keys a
// scenario may write under a pipeline's detectors read as one list.

#include "common/options_table.h"
#include "slam/features/ceiling_lamps.h"
#include "slam/features/corner_patches.h"
#include "slam/features/door_plate_detector.h"
#include "slam/features/door_plates.h"
#include "slam/features/harris_corners.h"
#include "slam/features/room_number_reader.h"
#include "slam/features/upward_doors.h"
#include "slam/features/vanishing_point.h"

namespace corridorsim::slam {

const OptionTable<CornerPatchOptions>& CornerPatchOptionsTable() {
  using O = CornerPatchOptions;
  return StaticOptionTable<O>([](OptionTable<O>& t) {
    t.AddEnum("detector", &O::detector,
              {{"fast", CornerDetector::kFast}, {"harris", CornerDetector::kHarris}},
              "corner detector: fast (P3) or harris (P2)");
    t.Add("fast_threshold", &O::fast_threshold, "grey levels",
          "FAST: intensity difference on the 16-pixel circle")
        .Range(1, 254);
    t.Add("harris_k", &O::harris_k, "", "Harris: k of det(M) - k trace(M)^2").Range(0.01, 0.25);
    t.Add("harris_quality", &O::harris_quality, "",
          "Harris: fraction of the best response a corner must reach")
        .RangeOpenLow(0, 1);
    t.Add("max_corners", &O::max_corners, "", "corners per image, strongest first").Range(1, 2000);
    t.Add("min_distance_px", &O::min_distance_px, "px", "spacing of kept corners").Range(0, 200);
    t.Add("patch_half_px", &O::patch_half_px, "px", "patch half side (patch 2 h + 1 square)")
        .Range(1, 15);
    t.Add("fast_subpixel_half_px", &O::fast_subpixel_half_px, "px",
          "FAST: half side of the cv::cornerSubPix window refining each corner (0 = integer pixel)")
        .Range(0, 10);
  });
}

const OptionTable<HarrisCornerOptions>& HarrisCornerOptionsTable() {
  using O = HarrisCornerOptions;
  return StaticOptionTable<O>([](OptionTable<O>& t) {
    t.Add("max_corners", &O::max_corners, "", "at most this many corners, strongest first")
        .Range(1, 10000);
    t.Add("quality_level", &O::quality_level, "",
          "a corner's response must reach this fraction of the best one")
        .RangeOpenLow(0, 1);
    t.Add("min_distance_px", &O::min_distance_px, "px",
          "no two corners closer than this; the stronger stays")
        .Range(0, 1000);
    t.Add("block_size_px", &O::block_size_px, "px",
          "side of the structure tensor's summation window")
        .Range(2, 31);
    t.Add("harris_k", &O::harris_k, "", "k of the response det(M) - k trace(M)^2")
        .Range(0.01, 0.25);
    t.Add("subpixel_half_window_px", &O::subpixel_half_window_px, "px",
          "cv::cornerSubPix half window (0 = the integer pixel of the maximum)")
        .Range(0, 15);
  });
}

const OptionTable<CeilingLampOptions>& CeilingLampOptionsTable() {
  using O = CeilingLampOptions;
  return StaticOptionTable<O>([](OptionTable<O>& t) {
    t.Add("brightness_threshold", &O::brightness_threshold, "grey level",
          "pixels above this are the image's brightest parts")
        .Range(1, 254);
    t.Add("min_area_px", &O::min_area_px, "px", "smallest bright region tested").Range(3, 1e6);
    t.Add("max_area_px", &O::max_area_px, "px", "largest bright region tested")
        .Range(3, 1e7)
        .Note(">= min_area_px");
    t.Add("max_regions", &O::max_regions, "", "regions tested per image, largest first")
        .Range(1, 1000);
    t.Add("canny_low", &O::canny_low, "grey levels/px", "Canny's lower threshold").Range(0, 5000);
    t.Add("canny_high", &O::canny_high, "grey levels/px", "Canny's upper threshold")
        .Range(0, 5000)
        .Note(">= canny_low");
    t.Add("min_edge_contrast", &O::min_edge_contrast, "grey levels",
          "grey step across a region's outline below which it is not a lamp (wall glare)")
        .Range(0, 255);
    t.Add("border_margin_px", &O::border_margin_px, "px",
          "edge points this close to the image border are ignored (P3 Fig. 3b)")
        .Range(0, 50);
    t.Add("min_edge_points", &O::min_edge_points, "", "fewer usable edge points: no test")
        .Range(3, 100000);
    t.Add("triples", &O::triples, "", "random three-point centres per region (P3 eqs. 1-2)")
        .Range(3, 10000);
    t.Add("min_chord_fraction", &O::min_chord_fraction, "",
          "shortest chord of a triple, as a fraction of the edge points' RMS spread")
        .Range(0, 2);
    t.Add("k_conv_px", &O::k_conv_px, "px",
          "K_conv: both principal standard deviations of the centres below it = circular")
        .Greater(0)
        .Range(0, 1000);
    t.Add("seed", &O::seed, "", "seed of the random triples");
  });
}

const OptionTable<UpwardDoorOptions>& UpwardDoorOptionsTable() {
  using O = UpwardDoorOptions;
  return StaticOptionTable<O>([](OptionTable<O>& t) {
    t.Add("lsd_scale", &O::lsd_scale, "", "image scale the Line Segment Detector works at")
        .RangeOpenLow(0, 1);
    t.Add("min_line_px", &O::min_line_px, "px", "shorter line segments are ignored")
        .Range(1, 10000);
    t.Add("radial_tolerance_deg", &O::radial_tolerance_deg, "deg",
          "a vertical line points at the principal point within this")
        .Range(0, 45);
    t.Add("min_radius_px", &O::min_radius_px, "px",
          "segments whose midpoint is nearer the principal point are ignored")
        .Range(0, 10000);
    t.Add("group_gap_deg", &O::group_gap_deg, "deg",
          "vertical lines this close in angle form one column (P3 Fig. 5a)")
        .Range(0, 45);
    t.Add("max_column_gap_px", &O::max_column_gap_px, "px",
          "radial gap between lines of one column at most")
        .Range(0, 10000);
    t.Add("min_column_px", &O::min_column_px, "px", "shortest radial extent of a column")
        .Range(0, 10000);
    t.Add("min_door_angle_deg", &O::min_door_angle_deg, "deg",
          "smallest angle between a door's columns about the principal point")
        .Range(0, 180);
    t.Add("max_door_angle_deg", &O::max_door_angle_deg, "deg", "largest such angle")
        .Range(0, 180)
        .Note(">= min_door_angle_deg");
    t.Add("max_top_ratio", &O::max_top_ratio, "",
          "largest ratio of the two column tops' distances from the principal point")
        .Range(1, 100);
    t.Add("bar_margin", &O::bar_margin, "",
          "the bar's ends may lie this fraction beyond the column tops (P3 Fig. 6b)")
        .Range(0, 1);
    t.Add("bar_angle_slack", &O::bar_angle_slack, "",
          "the bar's ends may lie this fraction of the columns' separation outside them (the "
          "frame's outer corners)")
        .Range(0, 1);
    t.Add("min_bar_coverage", &O::min_bar_coverage, "",
          "fraction of the columns' angular separation the bar lines must cover")
        .Range(0, 1);
    t.Add("max_lines", &O::max_lines, "", "line segments considered at most, longest first")
        .Range(1, 100000);
    t.Add("max_columns", &O::max_columns, "", "columns kept at most, longest first").Range(2, 1000);
    t.Add("max_candidates", &O::max_candidates, "", "door candidates kept at most").Range(1, 10000);
  });
}

const OptionTable<DoorPlateDetectorOptions>& DoorPlateDetectorOptionsTable() {
  using O = DoorPlateDetectorOptions;
  return StaticOptionTable<O>([](OptionTable<O>& t) {
    t.Add("scales", &O::scales, "", "image scales searched for digit-sized blobs, each in (0, 1]")
        .Note("1 to 6 values in (0, 1]");
    t.Add("edge_threshold", &O::edge_threshold, "", "|Sobel x| (3x3) that counts as an edge")
        .Range(1, 1020);
    t.Add("close_width_px", &O::close_width_px, "px", "closing kernel width (merges digits)")
        .Range(1, 31);
    t.Add("close_height_px", &O::close_height_px, "px", "closing kernel height").Range(1, 31);
    t.Add("min_height_px", &O::min_height_px, "px", "smallest blob height at a scale")
        .Range(1, 1000);
    t.Add("max_height_px", &O::max_height_px, "px", "largest blob height at a scale")
        .Range(1, 1000)
        .Note(">= min_height_px");
    t.Add("min_width_px", &O::min_width_px, "px", "smallest blob width at a scale").Range(1, 4000);
    t.Add("max_width_px", &O::max_width_px, "px", "largest blob width at a scale")
        .Range(1, 4000)
        .Note(">= min_width_px");
    t.Add("min_aspect", &O::min_aspect, "", "smallest blob width / height").Range(0.05, 50);
    t.Add("max_aspect", &O::max_aspect, "", "largest blob width / height")
        .Range(0.05, 50)
        .Note(">= min_aspect");
    t.Add("min_edge_fill", &O::min_edge_fill, "", "fraction of edge pixels in a blob's box")
        .Range(0, 1);
    t.Add("max_candidates", &O::max_candidates, "", "candidates kept per image").Range(1, 10000);
    t.Add("duplicate_iou", &O::duplicate_iou, "", "IoU above which two candidates are one")
        .RangeOpenLow(0, 1);
    t.Add("suppression_iou", &O::suppression_iou, "",
          "IoU above which the lower-scored of two detections is dropped")
        .RangeOpenLow(0, 1);
    t.Add("patch_width_px", &O::patch_width_px, "px", "P1 eq. 5 patch width").Range(4, 256);
    t.Add("patch_height_px", &O::patch_height_px, "px", "P1 eq. 5 patch height").Range(4, 256);
    t.Add("context", &O::context, "", "box fraction added on each side of the patch").Range(0, 2);
    t.Add("hog_cell_px", &O::hog_cell_px, "px",
          "HOG cell side appended to the patch's pixels (0 = pixels only)")
        .ZeroOr(2, 32)
        .Note("divides both patch sides, at least 2 cells each");
  });
}

const OptionTable<DoorPlateOptions>& DoorPlateOptionsTable() {
  return StaticOptionTable<DoorPlateOptions>([](OptionTable<DoorPlateOptions>& t) {
    t.AddSection("detector", &DoorPlateOptions::detector, DoorPlateDetectorOptionsTable(),
                 "P1 section 3.1 candidate segmentation and SVM patch",
                 &DoorPlateDetectorOptions::Check);
    t.AddSection("reader", &DoorPlateOptions::reader, RoomNumberReaderOptionsTable(),
                 "P1 section 3.2 digit segmentation and MLP", &RoomNumberReaderOptions::Check);
    t.Add("min_plate_score", &DoorPlateOptions::min_plate_score, "",
          "SVM margins above this are plates (P1 eq. 6: 0)")
        .Range(-100, 100);
  });
}

const OptionTable<RoomNumberReaderOptions>& RoomNumberReaderOptionsTable() {
  using O = RoomNumberReaderOptions;
  return StaticOptionTable<O>([](OptionTable<O>& t) {
    t.Add("margin", &O::margin, "", "box height fraction added on each side").Range(0, 2);
    t.Add("work_height_px", &O::work_height_px, "px", "the box is rescaled to this height")
        .Range(8, 512);
    t.Add("min_digit_height", &O::min_digit_height, "", "digit height / box height, at least")
        .Range(0.05, 5);
    t.Add("max_digit_height", &O::max_digit_height, "", "digit height / box height, at most")
        .Range(0.05, 5)
        .Note(">= min_digit_height");
    t.Add("max_digit_aspect", &O::max_digit_aspect, "", "digit width / height, at most")
        .Range(0.05, 10);
    t.Add("min_digits", &O::min_digits, "", "fewest digits of an accepted reading").Range(1, 16);
    t.Add("max_digits", &O::max_digits, "", "most digits of an accepted reading")
        .Range(1, 16)
        .Note(">= min_digits");
    t.Add("cell_width_px", &O::cell_width_px, "px", "P1 Fig. 7b cell width").Range(2, 64);
    t.Add("cell_height_px", &O::cell_height_px, "px", "P1 Fig. 7b cell height").Range(2, 64);
    t.Add("zone_cols", &O::zone_cols, "", "zoning grid columns (0 with zone_rows 0: off)")
        .Range(0, 16)
        .Note("<= cell_width_px");
    t.Add("zone_rows", &O::zone_rows, "", "zoning grid rows")
        .Range(0, 16)
        .Note("<= cell_height_px");
    t.Add("min_digit_score", &O::min_digit_score, "", "P1 Fig. 8: every digit's score, at least")
        .Range(0, 1);
  });
}

const OptionTable<VanishingPointOptions>& VanishingPointOptionsTable() {
  using O = VanishingPointOptions;
  return StaticOptionTable<O>([](OptionTable<O>& t) {
    t.Add("blur_sigma_px", &O::blur_sigma_px, "px",
          "Gaussian smoothing before Canny, standard deviation (0 = none)")
        .Range(0, 10);
    t.Add("canny_low", &O::canny_low, "grey levels/px",
          "Canny's lower hysteresis threshold (L2 gradient of the 3x3 Sobel)")
        .Range(0, 5000);
    t.Add("canny_high", &O::canny_high, "grey levels/px", "Canny's upper hysteresis threshold")
        .Range(0, 5000)
        .Note(">= canny_low");
    t.AddEnum("hough", &O::hough, kHoughMethodNames,
              "probabilistic (cv::HoughLinesP, segments) or standard (cv::HoughLines, infinite "
              "lines clipped to the image)");
    t.Add("hough_rho_px", &O::hough_rho_px, "px", "distance resolution of the Hough accumulator")
        .Range(0.1, 10);
    t.Add("hough_theta_deg", &O::hough_theta_deg, "deg", "angle resolution of the accumulator")
        .Range(0.05, 10);
    t.Add("hough_votes", &O::hough_votes, "", "accumulator threshold: edge pixels on a line")
        .Range(1, 10000);
    t.Add("min_line_length_px", &O::min_line_length_px, "px",
          "probabilistic: the shortest segment kept")
        .Range(0, 10000);
    t.Add("max_line_gap_px", &O::max_line_gap_px, "px",
          "probabilistic: the largest gap bridged within one segment")
        .Range(0, 1000);
    t.Add("merge_angle_deg", &O::merge_angle_deg, "deg",
          "segments within this angle and merge_distance_px of a longer one are one line")
        .Range(0, 10);
    t.Add("merge_distance_px", &O::merge_distance_px, "px",
          "the largest distance of a merged segment's ends from the longer one's line")
        .Range(0, 20);
    t.Add("refine_band_px", &O::refine_band_px, "px",
          "each line is re-fitted to the edge pixels within this distance (0 = Hough's line)")
        .Range(0, 10);
    t.Add("axis_reject_deg", &O::axis_reject_deg, "deg",
          "P1 section 2: lines within this angle of the u or v axis are rejected")
        .RangeOpenHigh(0, 45);
    t.Add("max_lines", &O::max_lines, "", "at most this many candidates enter the solve")
        .Range(2, 500);
    t.Add("min_lines", &O::min_lines, "", "fewer lines after the rejections: no point")
        .Range(2, 500)
        .Note("<= max_lines");
    t.Add("min_directions", &O::min_directions, "",
          "fewer distinct directions (merge_angle_deg apart) among the agreeing lines: no point")
        .Range(2, 500)
        .Note("<= min_lines");
    t.Add("weighted", &O::weighted, "",
          "beyond P1: eq. 4 weighted by each line's fit precision at the point (false: equal "
          "weights, as P1)");
    t.Add("outlier_distance_px", &O::outlier_distance_px, "px",
          "consensus and outlier pass (beyond P1): lines farther from the point disagree")
        .Greater(0)
        .AtMost(1000);
    t.Add("max_rms_residual_px", &O::max_rms_residual_px, "px",
          "no point when the kept lines' RMS distance to it is larger")
        .Greater(0)
        .AtMost(1000);
    t.Add("min_direction_spread_deg", &O::min_direction_spread_deg, "deg",
          "no point when the lines' normals spread less (RMS angle): nearly parallel lines")
        .Range(0, 45);
    t.Add("max_outside_image_px", &O::max_outside_image_px, "px",
          "no point farther than this outside the image rectangle")
        .Range(0, 100000);
  });
}

}  // namespace corridorsim::slam
