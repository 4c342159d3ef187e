#include "worlds/image_io.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace corridorsim {
namespace {

std::string Encode(const cv::Mat& bgr, const std::string& what) {
  std::vector<std::uint8_t> buffer;
  // zlib level 1: a noisy 640x480 camera frame encodes in 15 ms (level 6: 73 ms) for 17 % more
  // bytes; runs that save or export every frame are bound by this.
  if (!cv::imencode(".png", bgr, buffer, {cv::IMWRITE_PNG_COMPRESSION, 1})) {
    throw std::runtime_error(what + ": PNG encoding failed");
  }
  return std::string(buffer.begin(), buffer.end());
}

}  // namespace

std::string EncodePng(const Image8& image, const std::string& what) {
  const bool valid = image.width > 0 && image.height > 0 &&
                     (image.channels == 1 || image.channels == 3 || image.channels == 4) &&
                     image.data.size() == std::size_t(image.width) * image.height * image.channels;
  if (!valid) throw std::invalid_argument(what + ": image has inconsistent size or channels");
  const cv::Mat rgb(image.height, image.width, CV_8UC(image.channels),
                    const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat bgr;
  if (image.channels == 3) {
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  } else if (image.channels == 4) {
    cv::cvtColor(rgb, bgr, cv::COLOR_RGBA2BGRA);
  } else {
    bgr = rgb;
  }
  return Encode(bgr, what);
}

std::string EncodeJpegShrunk(const Image8& image, int max_width, int quality,
                             const std::string& what, double* scale) {
  const bool valid = image.width > 0 && image.height > 0 && image.channels == 3 &&
                     image.data.size() == std::size_t(image.width) * image.height * 3;
  if (!valid) throw std::invalid_argument(what + ": not an RGB image of consistent size");
  if (max_width < 1 || quality < 1 || quality > 100) {
    throw std::invalid_argument(what + ": JPEG width or quality out of range");
  }
  const cv::Mat rgb(image.height, image.width, CV_8UC3,
                    const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  double s = 1.0;
  if (image.width > max_width) {
    s = static_cast<double>(max_width) / image.width;
    const int height = std::max(1, static_cast<int>(std::lround(image.height * s)));
    cv::Mat shrunk;
    cv::resize(bgr, shrunk, cv::Size(max_width, height), 0, 0, cv::INTER_AREA);
    bgr = shrunk;
  }
  std::vector<std::uint8_t> buffer;
  if (!cv::imencode(".jpg", bgr, buffer,
                    {cv::IMWRITE_JPEG_QUALITY, quality, cv::IMWRITE_JPEG_OPTIMIZE, 1})) {
    throw std::runtime_error(what + ": JPEG encoding failed");
  }
  if (scale != nullptr) *scale = s;
  return std::string(buffer.begin(), buffer.end());
}

std::string EncodePng16(int width, int height, int channels, const std::vector<std::uint16_t>& data,
                        const std::string& what) {
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 3) ||
      data.size() != std::size_t(width) * height * channels) {
    throw std::invalid_argument(what + ": 16-bit image has inconsistent size or channels");
  }
  const cv::Mat rgb(height, width, CV_16UC(channels), const_cast<std::uint16_t*>(data.data()));
  cv::Mat bgr;
  if (channels == 3) {
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  } else {
    bgr = rgb;
  }
  return Encode(bgr, what);
}

}  // namespace corridorsim
