#include "slam/features/door_plate_detector.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>

namespace corridorsim::slam {

double IntersectionOverUnion(const BoxPx& a, const BoxPx& b) {
  const double ix = std::min(a.max_x, b.max_x) - std::max(a.min_x, b.min_x);
  const double iy = std::min(a.max_y, b.max_y) - std::max(a.min_y, b.min_y);
  if (!(ix > 0) || !(iy > 0) || !(a.width() > 0) || !(a.height() > 0) || !(b.width() > 0) ||
      !(b.height() > 0)) {
    return 0.0;
  }
  const double inter = ix * iy;
  return inter / (a.width() * a.height() + b.width() * b.height() - inter);
}

std::optional<OptionsProblem> DoorPlateDetectorOptions::Check() const {
  if (auto p = CheckOptionBounds(DoorPlateDetectorOptionsTable(), *this)) return p;
  if (scales.empty() || scales.size() > 6)
    return OptionsProblem{"scales", "must hold 1 to 6 values"};
  for (const double s : scales) {
    if (!(s > 0.0 && s <= 1.0)) return OptionsProblem{"scales", "each scale must lie in (0, 1]"};
  }
  if (max_height_px < min_height_px) {
    return OptionsProblem{"max_height_px", "must be at least min_height_px"};
  }
  if (max_width_px < min_width_px) {
    return OptionsProblem{"max_width_px", "must be at least min_width_px"};
  }
  if (max_aspect < min_aspect) return OptionsProblem{"max_aspect", "must be at least min_aspect"};
  if (hog_cell_px > 0 && (patch_width_px % hog_cell_px != 0 || patch_height_px % hog_cell_px != 0 ||
                          patch_width_px < 2 * hog_cell_px || patch_height_px < 2 * hog_cell_px)) {
    return OptionsProblem{"hog_cell_px",
                          "must divide patch_width_px and patch_height_px, at least 2 cells each"};
  }
  return std::nullopt;
}

cv::Mat GreyImage(const Image8& image, const cv::Rect& region) {
  CheckOrDie(image.width > 0 && image.height > 0 &&
                 image.data.size() == std::size_t(image.width) * image.height * image.channels,
             "slam::GreyImage", "the image is empty or its size does not match its buffer");
  const int type = image.channels == 1 ? CV_8UC1 : image.channels == 3 ? CV_8UC3 : CV_8UC4;
  CheckOrDie(image.channels == 1 || image.channels == 3 || image.channels == 4, "slam::GreyImage",
             "the image has neither 1, 3 nor 4 channels");
  CheckOrDie(region.x >= 0 && region.y >= 0 && region.width > 0 && region.height > 0 &&
                 region.x + region.width <= image.width && region.y + region.height <= image.height,
             "slam::GreyImage", "the region is empty or leaves the image");
  const cv::Mat view = cv::Mat(image.height, image.width, type,
                               const_cast<std::uint8_t*>(image.data.data()))(region);
  cv::Mat grey;
  if (image.channels == 1) {
    grey = view.clone();
  } else {
    cv::cvtColor(view, grey, image.channels == 3 ? cv::COLOR_RGB2GRAY : cv::COLOR_RGBA2GRAY);
  }
  return grey;
}

cv::Mat GreyImage(const Image8& image) {
  return GreyImage(image, cv::Rect(0, 0, image.width, image.height));
}

namespace {

std::vector<BoxPx> SegmentGrey(const cv::Mat& grey, const DoorPlateDetectorOptions& o) {
  std::vector<BoxPx> boxes;
  for (const double scale : o.scales) {
    cv::Mat small;
    if (scale == 1.0) {
      small = grey;
    } else {
      const cv::Size size(std::max(1, int(std::lround(grey.cols * scale))),
                          std::max(1, int(std::lround(grey.rows * scale))));
      cv::resize(grey, small, size, 0, 0, cv::INTER_AREA);
    }
    const double sx = double(grey.cols) / small.cols, sy = double(grey.rows) / small.rows;
    // P1 section 3.1: vertical edges (Sobel in x), threshold, closing, contours.
    cv::Mat gx, edges;
    cv::Sobel(small, gx, CV_16S, 1, 0, 3);
    gx = cv::abs(gx);
    cv::Mat edge_mask = gx > o.edge_threshold;
    cv::Mat closed;
    cv::morphologyEx(
        edge_mask, closed, cv::MORPH_CLOSE,
        cv::getStructuringElement(cv::MORPH_RECT, cv::Size(o.close_width_px, o.close_height_px)));
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(closed, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    for (const auto& contour : contours) {
      const cv::Rect r = cv::boundingRect(contour);
      if (r.height < o.min_height_px || r.height > o.max_height_px) continue;
      if (r.width < o.min_width_px || r.width > o.max_width_px) continue;
      const double aspect = double(r.width) / r.height;
      if (aspect < o.min_aspect || aspect > o.max_aspect) continue;
      const double fill = cv::countNonZero(edge_mask(r)) / double(r.area());
      if (fill < o.min_edge_fill) continue;
      // The blob's pixel edges in the full image (pixel-centre convention).
      boxes.push_back(BoxPx{r.x * sx - 0.5, r.y * sy - 0.5, (r.x + r.width) * sx - 0.5,
                            (r.y + r.height) * sy - 0.5});
    }
  }
  // Duplicates across scales: the first (finest scale) is kept.
  std::vector<BoxPx> kept;
  for (const BoxPx& b : boxes) {
    bool duplicate = false;
    for (const BoxPx& k : kept) {
      if (IntersectionOverUnion(b, k) > o.duplicate_iou) {
        duplicate = true;
        break;
      }
    }
    if (!duplicate) kept.push_back(b);
    if (static_cast<int>(kept.size()) >= o.max_candidates) break;
  }
  return kept;
}

cv::Mat PatchFeaturesGrey(const cv::Mat& grey, const BoxPx& box,
                          const DoorPlateDetectorOptions& o) {
  const double cw = box.width() * o.context, ch = box.height() * o.context;
  const int x0 = std::clamp(int(std::floor(box.min_x + 0.5 - cw)), 0, grey.cols - 1);
  const int y0 = std::clamp(int(std::floor(box.min_y + 0.5 - ch)), 0, grey.rows - 1);
  const int x1 = std::clamp(int(std::ceil(box.max_x + 0.5 + cw)), x0 + 1, grey.cols);
  const int y1 = std::clamp(int(std::ceil(box.max_y + 0.5 + ch)), y0 + 1, grey.rows);
  cv::Mat patch;
  cv::resize(grey(cv::Rect(x0, y0, x1 - x0, y1 - y0)), patch,
             cv::Size(o.patch_width_px, o.patch_height_px), 0, 0, cv::INTER_AREA);
  // Polarity: the text (Otsu's minority class) is made dark.
  cv::Mat binary;
  cv::threshold(patch, binary, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  if (std::size_t(cv::countNonZero(binary)) * 2 < binary.total()) patch = 255 - patch;
  cv::Mat f;
  patch.convertTo(f, CV_32F);
  cv::Scalar mean, stddev;
  cv::meanStdDev(f, mean, stddev);
  f = (f - mean[0]) / std::max(stddev[0], 1.0);
  f = f.reshape(1, 1);
  if (o.hog_cell_px == 0) return f.clone();
  const int c = o.hog_cell_px;
  const cv::HOGDescriptor hog(patch.size(), cv::Size(2 * c, 2 * c), cv::Size(c, c), cv::Size(c, c),
                              9);
  std::vector<float> descriptor;
  hog.compute(patch, descriptor);
  cv::Mat row;
  cv::hconcat(f, cv::Mat(1, int(descriptor.size()), CV_32F, descriptor.data()), row);
  return row;
}

}  // namespace

std::vector<BoxPx> SegmentPlateCandidates(const Image8& image,
                                          const DoorPlateDetectorOptions& options) {
  return SegmentGrey(GreyImage(image), options);
}

cv::Mat PlatePatchFeatures(const Image8& image, const BoxPx& box,
                           const DoorPlateDetectorOptions& options) {
  return PatchFeaturesGrey(GreyImage(image), box, options);
}

int PlateFeatureCount(const DoorPlateDetectorOptions& o) {
  const int pixels = o.patch_width_px * o.patch_height_px;
  if (o.hog_cell_px == 0) return pixels;
  // Blocks of 2 x 2 cells a cell apart: (cells - 1) per side, 4 cells of 9 bins each.
  const int blocks_x = o.patch_width_px / o.hog_cell_px - 1;
  const int blocks_y = o.patch_height_px / o.hog_cell_px - 1;
  return pixels + blocks_x * blocks_y * 4 * 9;
}

double PlateScore(const cv::ml::SVM& svm, const cv::Mat& features) {
  // OpenCV's two-class decision value is positive for the first (smaller) label, -1 here: the
  // margin of the plate class (+1) is its negative.
  return -svm.predict(features, cv::noArray(), cv::ml::StatModel::RAW_OUTPUT);
}

std::vector<PlateCandidate> ScorePlateCandidates(const Image8& image, const cv::ml::SVM& svm,
                                                 const DoorPlateDetectorOptions& options) {
  const cv::Mat grey = GreyImage(image);
  std::vector<PlateCandidate> scored;
  for (const BoxPx& box : SegmentGrey(grey, options)) {
    scored.push_back(PlateCandidate{box, PlateScore(svm, PatchFeaturesGrey(grey, box, options))});
  }
  std::stable_sort(
      scored.begin(), scored.end(),
      [](const PlateCandidate& a, const PlateCandidate& b) { return a.score > b.score; });
  return scored;
}

std::vector<std::size_t> SuppressOverlapping(const std::vector<BoxPx>& boxes, double max_iou) {
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const bool suppressed = std::any_of(kept.begin(), kept.end(), [&](std::size_t k) {
      return IntersectionOverUnion(boxes[i], boxes[k]) > max_iou;
    });
    if (!suppressed) kept.push_back(i);
  }
  return kept;
}

}  // namespace corridorsim::slam
