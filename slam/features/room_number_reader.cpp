#include "slam/features/room_number_reader.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace corridorsim::slam {

std::optional<OptionsProblem> RoomNumberReaderOptions::Check() const {
  if (auto p = CheckOptionBounds(RoomNumberReaderOptionsTable(), *this)) return p;
  if (max_digit_height < min_digit_height) {
    return OptionsProblem{"max_digit_height", "must be at least min_digit_height"};
  }
  if (max_digits < min_digits) return OptionsProblem{"max_digits", "must be at least min_digits"};
  if ((zone_cols == 0) != (zone_rows == 0)) {
    return OptionsProblem{"zone_rows", "zone_cols and zone_rows are both 0 (off) or both set"};
  }
  if (zone_cols > cell_width_px)
    return OptionsProblem{"zone_cols", "must be at most cell_width_px"};
  if (zone_rows > cell_height_px) {
    return OptionsProblem{"zone_rows", "must be at most cell_height_px"};
  }
  return std::nullopt;
}

int DigitFeatureCount(const RoomNumberReaderOptions& o) {
  return o.cell_height_px + o.cell_width_px + 1 + o.zone_cols * o.zone_rows;
}

namespace {

// The digit boxes of a binary crop (strokes = 255), left to right, at most max_digits + 1.
std::vector<cv::Rect> DigitRects(const cv::Mat& binary, const RoomNumberReaderOptions& o) {
  std::vector<std::vector<cv::Point>> contours;
  // Every stroke component's outer boundary (RETR_CCOMP: also those inside a hole of another,
  // as digits inside a ring of the plate's border or the wall).
  std::vector<cv::Vec4i> hierarchy;
  cv::findContours(binary.clone(), contours, hierarchy, cv::RETR_CCOMP, cv::CHAIN_APPROX_SIMPLE);
  std::vector<cv::Rect> rects, wide;
  for (std::size_t i = 0; i < contours.size(); ++i) {
    if (hierarchy[i][3] >= 0) continue;  // a hole
    const cv::Rect r = cv::boundingRect(contours[i]);
    // Parts of the plate's border or frame reach the crop's edge; digits do not.
    if (r.x == 0 || r.y == 0 || r.x + r.width == binary.cols || r.y + r.height == binary.rows)
      continue;
    const double h = double(r.height) / o.work_height_px;
    if (h < o.min_digit_height || h > o.max_digit_height) continue;
    (r.width <= o.max_digit_aspect * r.height ? rects : wide).push_back(r);
  }
  // The digit width: the median of the single digits' widths, less the narrow ones ("1"), else
  // 0.65 heights.
  std::vector<int> widths;
  for (const cv::Rect& r : rects) {
    if (r.width >= 0.4 * r.height) widths.push_back(r.width);
  }
  std::sort(widths.begin(), widths.end());
  for (const cv::Rect& r : wide) {
    const double digit_width = widths.empty() ? 0.65 * r.height : widths[widths.size() / 2];
    // Digits that the threshold joined (tight fonts, small plates): cut at the columns of least
    // ink near the equal division into round(width / digit width) digits.
    const int n = int(std::lround(r.width / digit_width));
    if (n < 2 || n > o.max_digits) continue;
    cv::Mat ink;
    cv::reduce(binary(r), ink, 0, cv::REDUCE_SUM, CV_32S);
    int start = 0;
    for (int k = 1; k <= n; ++k) {
      int cut = r.width;
      if (k < n) {
        const int centre = r.width * k / n, half = std::max(1, r.width / (4 * n));
        cut = centre;
        for (int x = std::max(1, centre - half); x <= std::min(r.width - 2, centre + half); ++x) {
          if (ink.at<int>(0, x) < ink.at<int>(0, cut)) cut = x;
        }
      }
      if (cut - start >= 2) {
        // The piece's rows with ink bound it vertically.
        const cv::Rect column(r.x + start, r.y, cut - start, r.height);
        cv::Mat rows;
        cv::reduce(binary(column), rows, 1, cv::REDUCE_MAX);
        int top = 0, bottom = r.height - 1;
        while (top < bottom && rows.at<std::uint8_t>(top, 0) == 0) ++top;
        while (bottom > top && rows.at<std::uint8_t>(bottom, 0) == 0) --bottom;
        rects.push_back(cv::Rect(column.x, r.y + top, column.width, bottom - top + 1));
      }
      start = cut;
    }
  }
  std::sort(rects.begin(), rects.end(), [](const cv::Rect& a, const cv::Rect& b) {
    return a.x != b.x ? a.x < b.x : a.y < b.y;
  });
  // A digit broken in two by the threshold: boxes overlapping by half the narrower are merged.
  std::vector<cv::Rect> merged;
  for (const cv::Rect& r : rects) {
    if (!merged.empty()) {
      cv::Rect& last = merged.back();
      const int overlap = std::min(last.x + last.width, r.x + r.width) - std::max(last.x, r.x);
      if (overlap * 2 > std::min(last.width, r.width)) {
        last |= r;
        continue;
      }
    }
    merged.push_back(r);
    if (static_cast<int>(merged.size()) > o.max_digits) break;
  }

  return merged;
}

}  // namespace

std::vector<DigitSegment> SegmentDigits(const Image8& image, const BoxPx& box,
                                        const RoomNumberReaderOptions& o) {
  CheckOrDie(image.width > 0 && image.height > 0, "slam::SegmentDigits", "an empty image");
  if (!(box.width() > 0) || !(box.height() > 0)) return {};
  const double m = box.height() * o.margin;
  const int x0 = std::clamp(int(std::floor(box.min_x + 0.5 - m)), 0, image.width - 1);
  const int y0 = std::clamp(int(std::floor(box.min_y + 0.5 - m)), 0, image.height - 1);
  const int x1 = std::clamp(int(std::ceil(box.max_x + 0.5 + m)), x0 + 1, image.width);
  const int y1 = std::clamp(int(std::ceil(box.max_y + 0.5 + m)), y0 + 1, image.height);
  // Only the crop is converted: DetectDoorPlates reads several candidates per image.
  const cv::Mat grey = GreyImage(image, cv::Rect(x0, y0, x1 - x0, y1 - y0));
  // Rescaled so that the box is work_height_px high (bounded: the box is inside the image).
  const double k = o.work_height_px / box.height();
  const cv::Size size(std::clamp(int(std::lround((x1 - x0) * k)), 1, 64 * o.work_height_px),
                      std::clamp(int(std::lround((y1 - y0) * k)), 1, 8 * o.work_height_px));
  cv::Mat crop;
  cv::resize(grey, crop, size, 0, 0, cv::INTER_LINEAR);
  cv::Mat binary;
  cv::threshold(crop, binary, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  const cv::Rect inner =
      cv::Rect(int(std::lround((box.min_x + 0.5 - x0) * k)),
               int(std::lround((box.min_y + 0.5 - y0) * k)), int(std::lround(box.width() * k)),
               int(std::lround(box.height() * k))) &
      cv::Rect(0, 0, binary.cols, binary.rows);

  // Text = 255. The polarity that gives more digits (up to max_digits) wins; on a tie, the one
  // whose strokes are the minority inside the box (the margin may hold the plate's border or
  // the wall, of either polarity, and bold strokes may fill most of a tight box).
  const cv::Mat inverted = 255 - binary;
  std::vector<cv::Rect> merged = DigitRects(binary, o);
  const std::vector<cv::Rect> merged_inverted = DigitRects(inverted, o);
  const auto valid = [&](const std::vector<cv::Rect>& r) {
    return std::min<int>(int(r.size()), o.max_digits);
  };
  const bool minority_inverted =
      inner.area() > 0 && cv::countNonZero(binary(inner)) * 2 > inner.area();
  if (valid(merged_inverted) > valid(merged) ||
      (valid(merged_inverted) == valid(merged) && minority_inverted)) {
    merged = merged_inverted;
    binary = inverted;
  }

  std::vector<DigitSegment> out;
  for (const cv::Rect& r : merged) {
    DigitSegment d;
    d.box_px = BoxPx{x0 + r.x / k - 0.5, y0 + r.y / k - 0.5, x0 + (r.x + r.width) / k - 0.5,
                     y0 + (r.y + r.height) / k - 0.5};
    // P1 Fig. 7b: projections of the digit resized to the cell.
    cv::Mat cell;
    cv::resize(binary(r), cell, cv::Size(o.cell_width_px, o.cell_height_px), 0, 0, cv::INTER_AREA);
    cv::Mat cf;
    cell.convertTo(cf, CV_32F, 1.0 / 255.0);
    d.features = cv::Mat(1, DigitFeatureCount(o), CV_32F);
    float* f = d.features.ptr<float>(0);
    int n = 0;
    for (int y = 0; y < o.cell_height_px; ++y)
      f[n++] = float(cv::sum(cf.row(y))[0] / o.cell_width_px);
    for (int x = 0; x < o.cell_width_px; ++x)
      f[n++] = float(cv::sum(cf.col(x))[0] / o.cell_height_px);
    f[n++] = float(double(r.width) / r.height);
    if (o.zone_cols > 0) {
      cv::Mat zones;
      cv::resize(cf, zones, cv::Size(o.zone_cols, o.zone_rows), 0, 0, cv::INTER_AREA);
      for (int y = 0; y < o.zone_rows; ++y) {
        for (int x = 0; x < o.zone_cols; ++x) f[n++] = zones.at<float>(y, x);
      }
    }
    out.push_back(std::move(d));
  }
  return out;
}

DigitReading ClassifyDigit(const cv::ml::ANN_MLP& mlp, const cv::Mat& features) {
  cv::Mat outputs;
  mlp.predict(features, outputs);
  cv::Point best;
  double best_value = 0.0;
  cv::minMaxLoc(outputs.reshape(1, 1), nullptr, &best_value, nullptr, &best);
  DigitReading d;
  d.digit = static_cast<char>('0' + best.x);
  // Trained on targets -1 / +1: the winning output mapped to [0, 1] (P1 Fig. 8).
  d.score = std::clamp((best_value + 1.0) / 2.0, 0.0, 1.0);
  return d;
}

RoomNumberReading ReadRoomNumber(const Image8& image, const BoxPx& box, const cv::ml::ANN_MLP& mlp,
                                 const RoomNumberReaderOptions& options) {
  RoomNumberReading reading;
  const std::vector<DigitSegment> segments = SegmentDigits(image, box, options);
  for (const DigitSegment& s : segments) {
    DigitReading d = ClassifyDigit(mlp, s.features);
    d.box_px = s.box_px;
    reading.number.push_back(d.digit);
    reading.digits.push_back(d);
  }
  if (!reading.digits.empty()) {
    reading.min_score = 1.0;
    for (const DigitReading& d : reading.digits)
      reading.min_score = std::min(reading.min_score, d.score);
  }
  const int n = static_cast<int>(reading.digits.size());
  reading.accepted = n >= options.min_digits && n <= options.max_digits &&
                     reading.min_score >= options.min_digit_score;
  return reading;
}

}  // namespace corridorsim::slam
