#pragma once
// P1 section 3.2: reading the room number of a detected plate. The number region is binarised
// (Otsu), its digits segmented by contours (ordered left to right, filtered by size), each digit
// described by the horizontal and vertical projection histograms of its binary image resized to
// a fixed cell (P1 Fig. 7b) and classified by a multi-layer perceptron (digits 0-9). A digit's
// score is the network's output for the winning class mapped to [0, 1] (P1 Fig. 8); a plate is
// accepted only if every digit's score clears min_digit_score (P1: true readings score ~1.0,
// false ones <= 0.7). Pure functions of an image and a box.

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include "common/error.h"
#include "common/image.h"
#include "common/options_table.h"
#include "slam/features/door_plate_detector.h"

namespace corridorsim::slam {

struct RoomNumberReaderOptions {
  double margin = 0.2;            // fraction of the box height added on each side before Otsu
  int work_height_px = 48;        // the box is rescaled to this height before segmentation
  double min_digit_height = 0.5;  // a digit's height / the box's height, at least
  double max_digit_height = 1.6;  // at most
  double max_digit_aspect = 1.2;  // a digit's width / height, at most
  int min_digits = 3;             // readings with fewer or more digits are not accepted (the
                                  // corridors' room numbers have 3 digits)
  int max_digits = 5;
  int cell_width_px = 10;  // P1 Fig. 7b: the digit is resized to this cell
  int cell_height_px = 16;
  // Added to P1's projections (they alone confuse 6, 8, 9 and 0 of some fonts): the mean of the
  // binary cell over a zone_cols x zone_rows grid; 0 = off (P1's features only).
  int zone_cols = 5;
  int zone_rows = 8;
  double min_digit_score = 0.75;  // acceptance: every digit's score clears this (P1: false <= 0.7)
  std::optional<OptionsProblem> Check() const;
};
const OptionTable<RoomNumberReaderOptions>& RoomNumberReaderOptionsTable();

struct DigitSegment {
  BoxPx box_px;      // in the image's pixels
  cv::Mat features;  // 1 x DigitFeatureCount CV_32F
};
/// The number of features per digit: cell_height (row sums) + cell_width (column sums) + 1
/// (the digit's width / height: a "1" resized to the cell would otherwise look like a block)
/// + zone_cols * zone_rows (zoning).
int DigitFeatureCount(const RoomNumberReaderOptions& options);

/// The digits inside `box` of `image`, left to right (at most max_digits + 1 are returned so
/// that a reading with too many digits is seen as such).
std::vector<DigitSegment> SegmentDigits(const Image8& image, const BoxPx& box,
                                        const RoomNumberReaderOptions& options);

struct DigitReading {
  char digit = '?';
  double score = 0.0;  // the winning output mapped to [0, 1]
  BoxPx box_px;
};
struct RoomNumberReading {
  std::string number;  // the digits read, left to right
  std::vector<DigitReading> digits;
  double min_score = 0.0;  // over the digits (0 with none)
  bool accepted = false;   // digit count in bounds and every score >= min_digit_score
};

/// Classifies one digit's features: the winning digit and its score in [0, 1].
DigitReading ClassifyDigit(const cv::ml::ANN_MLP& mlp, const cv::Mat& features);

/// Reads the number region `box` of `image` with `mlp` (input DigitFeatureCount, output 10).
RoomNumberReading ReadRoomNumber(const Image8& image, const BoxPx& box, const cv::ml::ANN_MLP& mlp,
                                 const RoomNumberReaderOptions& options);

}  // namespace corridorsim::slam
