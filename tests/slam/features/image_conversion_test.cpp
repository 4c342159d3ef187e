// Tests slam/features/image_conversion.cpp: views share the image's bytes, conversions change
// channel order as documented.
#include "slam/features/image_conversion.h"

#include <catch2/catch.hpp>

namespace corridorsim::slam {
namespace {

Image8 Ramp(int width, int height, int channels) {
  Image8 image(width, height, channels);
  for (std::size_t i = 0; i < image.data.size(); ++i) {
    image.data[i] = static_cast<std::uint8_t>((i * 7) % 251);
  }
  return image;
}

TEST_CASE("MatView shares the image's bytes without copying", "[slam][features]") {
  const Image8 rgb = Ramp(5, 4, 3);
  const cv::Mat view = MatView(rgb);
  CHECK(view.data == rgb.data.data());
  CHECK(view.type() == CV_8UC3);
  CHECK(view.cols == 5);
  CHECK(view.rows == 4);
  CHECK(view.at<cv::Vec3b>(2, 3)[1] == rgb.Pixel(3, 2)[1]);

  ImageF depth(6, 2, 1.5f);
  depth.at(4, 1) = 2.5f;
  const cv::Mat depth_view = MatView(depth);
  CHECK(reinterpret_cast<const float*>(depth_view.data) == depth.data.data());
  CHECK(depth_view.at<float>(1, 4) == 2.5f);
}

TEST_CASE("GreyMat is a view of a grey image and BT.601 grey of an RGB one", "[slam][features]") {
  const Image8 grey = Ramp(5, 4, 1);
  CHECK(GreyMat(grey).data == grey.data.data());

  Image8 rgb(2, 1, 3);
  rgb.Pixel(0, 0)[0] = 255;  // pure red
  rgb.Pixel(1, 0)[2] = 255;  // pure blue
  const cv::Mat g = GreyMat(rgb);
  REQUIRE(g.type() == CV_8UC1);
  CHECK(g.at<std::uint8_t>(0, 0) == 76);  // 0.299 * 255: red is read as red, not as blue
  CHECK(g.at<std::uint8_t>(0, 1) == 29);  // 0.114 * 255
}

TEST_CASE("BgrMat and ImageFromMat swap the channel order both ways", "[slam][features]") {
  const Image8 rgb = Ramp(7, 3, 3);
  const cv::Mat bgr = BgrMat(rgb);
  REQUIRE(bgr.type() == CV_8UC3);
  CHECK(bgr.at<cv::Vec3b>(1, 2)[0] == rgb.Pixel(2, 1)[2]);
  CHECK(bgr.at<cv::Vec3b>(1, 2)[2] == rgb.Pixel(2, 1)[0]);
  const Image8 back = ImageFromMat(bgr);
  CHECK(back.channels == 3);
  CHECK(back.data == rgb.data);

  const Image8 grey = Ramp(4, 4, 1);
  const cv::Mat grey_bgr = BgrMat(grey);
  CHECK(grey_bgr.at<cv::Vec3b>(3, 1) ==
        cv::Vec3b(grey.Pixel(1, 3)[0], grey.Pixel(1, 3)[0], grey.Pixel(1, 3)[0]));
  CHECK(ImageFromMat(MatView(grey)).data == grey.data);

  const Image8 rgba = Ramp(3, 2, 4);
  const cv::Mat from_rgba = BgrMat(rgba);
  CHECK(from_rgba.at<cv::Vec3b>(1, 1)[0] == rgba.Pixel(1, 1)[2]);
}

}  // namespace
}  // namespace corridorsim::slam
