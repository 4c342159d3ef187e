#include "slam/features/image_conversion.h"

#include <cstring>

#include <opencv2/imgproc.hpp>

#include "common/error.h"

namespace corridorsim::slam {
namespace {

void CheckImage(const Image8& image) {
  CheckOrDie(image.width >= 0 && image.height >= 0 &&
                 (image.channels == 1 || image.channels == 3 || image.channels == 4) &&
                 image.data.size() ==
                     static_cast<std::size_t>(image.width) * image.height * image.channels,
             "slam::MatView", "an Image8 whose size, channels and data disagree");
}

}  // namespace

cv::Mat MatView(const Image8& image) {
  CheckImage(image);
  if (image.empty()) return cv::Mat(image.height, image.width, CV_8UC(image.channels));
  return cv::Mat(image.height, image.width, CV_8UC(image.channels),
                 const_cast<std::uint8_t*>(image.data.data()));
}

cv::Mat MatView(const ImageF& image) {
  CheckOrDie(image.width >= 0 && image.height >= 0 &&
                 image.data.size() == static_cast<std::size_t>(image.width) * image.height,
             "slam::MatView", "an ImageF whose size and data disagree");
  if (image.data.empty()) return cv::Mat(image.height, image.width, CV_32FC1);
  return cv::Mat(image.height, image.width, CV_32FC1, const_cast<float*>(image.data.data()));
}

cv::Mat GreyMat(const Image8& image) {
  const cv::Mat view = MatView(image);
  if (image.channels == 1) return view;
  if (image.empty()) return cv::Mat(image.height, image.width, CV_8UC1);
  cv::Mat grey;
  cv::cvtColor(view, grey, image.channels == 3 ? cv::COLOR_RGB2GRAY : cv::COLOR_RGBA2GRAY);
  return grey;
}

cv::Mat BgrMat(const Image8& image) {
  const cv::Mat view = MatView(image);
  cv::Mat bgr;
  if (image.empty()) return cv::Mat(image.height, image.width, CV_8UC3);
  switch (image.channels) {
    case 1:
      cv::cvtColor(view, bgr, cv::COLOR_GRAY2BGR);
      break;
    case 3:
      cv::cvtColor(view, bgr, cv::COLOR_RGB2BGR);
      break;
    default:
      cv::cvtColor(view, bgr, cv::COLOR_RGBA2BGR);
      break;
  }
  return bgr;
}

Image8 ImageFromMat(const cv::Mat& bgr_or_grey) {
  CheckOrDie(bgr_or_grey.type() == CV_8UC3 || bgr_or_grey.type() == CV_8UC1, "slam::ImageFromMat",
             "expected a CV_8UC3 (BGR) or CV_8UC1 matrix");
  const int channels = bgr_or_grey.channels();
  Image8 image(bgr_or_grey.cols, bgr_or_grey.rows, channels);
  if (image.empty()) return image;
  cv::Mat out = MatView(image);  // writes into image's bytes
  if (channels == 3) {
    cv::cvtColor(bgr_or_grey, out, cv::COLOR_BGR2RGB);
  } else {
    bgr_or_grey.copyTo(out);
  }
  return image;
}

}  // namespace corridorsim::slam
