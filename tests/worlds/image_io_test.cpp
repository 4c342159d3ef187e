#include "worlds/image_io.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

// worlds/image_io writes PNG and JPEG through libpng and libjpeg; until 2026-12-07 it called
// cv::imencode. These cases hold it to the same bytes as OpenCV's encoder with the settings it
// used (a run's frames, datasets and exports keep their bytes), and its decoder to what
// cv::imdecode(IMREAD_UNCHANGED) read.

namespace corridorsim {
namespace {

// Noise, smooth gradients and flat areas: every PNG filter and JPEG block kind gets used.
Image8 TestImage(int width, int height, int channels, std::uint32_t seed) {
  Image8 image(width, height, channels);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(0, 255);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c) {
        int v = 0;
        if (x < width / 3) {
          v = noise(rng);
        } else if (x < 2 * width / 3) {
          v = (x * 7 + y * 3 + c * 50) % 256;
        } else {
          v = 90 + 40 * c;
        }
        image.Pixel(x, y)[c] = static_cast<std::uint8_t>(v);
      }
    }
  }
  return image;
}

cv::Mat AsBgrMat(const Image8& image) {
  const cv::Mat rgb(image.height, image.width, CV_8UC(image.channels),
                    const_cast<std::uint8_t*>(image.data.data()));
  cv::Mat bgr;
  if (image.channels == 3) {
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  } else if (image.channels == 4) {
    cv::cvtColor(rgb, bgr, cv::COLOR_RGBA2BGRA);
  } else {
    bgr = rgb.clone();
  }
  return bgr;
}

std::string OpenCvPng(const cv::Mat& bgr) {
  std::vector<std::uint8_t> buffer;
  REQUIRE(cv::imencode(".png", bgr, buffer, {cv::IMWRITE_PNG_COMPRESSION, 1}));
  return std::string(buffer.begin(), buffer.end());
}

std::vector<std::uint8_t> Bytes(const std::string& text) {
  return std::vector<std::uint8_t>(text.begin(), text.end());
}

// A PNG written by libpng itself, for the kinds OpenCV cannot write: `header` sets IHDR (and a
// palette), `row` packs row y into its bytes; interlaced files get every pass.
std::vector<std::uint8_t> LibpngFile(int height,
                                     const std::function<void(png_structp, png_infop)>& header,
                                     const std::function<std::vector<std::uint8_t>(int)>& row) {
  std::vector<std::uint8_t> out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_set_write_fn(
      png, &out,
      [](png_structp p, png_bytep data, png_size_t size) {
        auto* o = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(p));
        o->insert(o->end(), data, data + size);
      },
      nullptr);
  header(png, info);
  png_write_info(png, info);
  const int passes = png_set_interlace_handling(png);
  for (int pass = 0; pass < passes; ++pass) {
    for (int y = 0; y < height; ++y) {
      std::vector<std::uint8_t> bytes = row(y);
      png_write_row(png, bytes.data());
    }
  }
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return out;
}

// A palette PNG (4 colours, 2 bits, one transparent, interlaced).
std::vector<std::uint8_t> PalettePng(int width, int height) {
  return LibpngFile(
      height,
      [&](png_structp png, png_infop info) {
        png_set_IHDR(png, info, width, height, 2, PNG_COLOR_TYPE_PALETTE, PNG_INTERLACE_ADAM7,
                     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
        png_color palette[4] = {{0, 0, 0}, {255, 0, 0}, {0, 200, 30}, {20, 40, 250}};
        png_set_PLTE(png, info, palette, 4);
        png_byte alpha[1] = {0};
        png_set_tRNS(png, info, alpha, 1, nullptr);
      },
      [&](int y) {
        std::vector<std::uint8_t> row((width * 2 + 7) / 8, 0);
        for (int x = 0; x < width; ++x) {
          row[x / 4] |= static_cast<std::uint8_t>(((x + y) % 4) << (6 - 2 * (x % 4)));
        }
        return row;
      });
}

// Grey of `bits` bits (1, 2 or 4 expand to 8 when read) or grey with alpha (bits 8, `alpha`).
std::vector<std::uint8_t> GreyPng(int width, int height, int bits, bool alpha) {
  const int channels = alpha ? 2 : 1;
  return LibpngFile(
      height,
      [&](png_structp png, png_infop info) {
        png_set_IHDR(png, info, width, height, bits,
                     alpha ? PNG_COLOR_TYPE_GRAY_ALPHA : PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
                     PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
      },
      [&](int y) {
        std::vector<std::uint8_t> row((width * channels * bits + 7) / 8, 0);
        for (int i = 0; i < width * channels; ++i) {
          const int value = (i * 37 + y * 11) % (1 << bits);
          const int shift = 8 - bits - (i * bits) % 8;
          row[(i * bits) / 8] |= static_cast<std::uint8_t>(value << shift);
        }
        return row;
      });
}

// What detect read before: cv::imdecode(IMREAD_UNCHANGED), 16 bits to 8, grey to BGR, alpha
// dropped, then RGB.
Image8 OpenCvRgb(const std::vector<std::uint8_t>& bytes) {
  cv::Mat image = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  REQUIRE_FALSE(image.empty());
  if (image.depth() == CV_16U) {
    cv::Mat eight;
    image.convertTo(eight, CV_8U, 1.0 / 257.0);
    image = eight;
  }
  cv::Mat rgb;
  if (image.channels() == 1) cv::cvtColor(image, rgb, cv::COLOR_GRAY2RGB);
  if (image.channels() == 3) cv::cvtColor(image, rgb, cv::COLOR_BGR2RGB);
  if (image.channels() == 4) cv::cvtColor(image, rgb, cv::COLOR_BGRA2RGB);
  Image8 out(rgb.cols, rgb.rows, 3);
  std::memcpy(out.data.data(), rgb.data, out.data.size());
  return out;
}

}  // namespace

TEST_CASE("8-bit PNGs are OpenCV's bytes for grey, RGB and RGBA", "[image_io]") {
  for (const int channels : {1, 3, 4}) {
    for (const auto& [w, h] : std::vector<std::pair<int, int>>{{1, 1}, {7, 5}, {320, 240}}) {
      const Image8 image = TestImage(w, h, channels, 17u + static_cast<std::uint32_t>(w));
      INFO(channels << " channels, " << w << "x" << h);
      CHECK(EncodePng(image, "test") == OpenCvPng(AsBgrMat(image)));
    }
  }
}

TEST_CASE("16-bit PNGs are OpenCV's bytes for grey and RGB", "[image_io]") {
  for (const int channels : {1, 3}) {
    const int w = 161, h = 97;
    std::vector<std::uint16_t> data(std::size_t(w) * h * channels);
    std::mt19937 rng(5);
    for (std::size_t i = 0; i < data.size(); ++i) {
      data[i] = static_cast<std::uint16_t>(i % 3 == 0 ? rng() : (i * 37) % 65536);
    }
    cv::Mat mat(h, w, CV_16UC(channels), data.data());
    cv::Mat bgr;
    if (channels == 3) {
      cv::cvtColor(mat, bgr, cv::COLOR_RGB2BGR);
    } else {
      bgr = mat;
    }
    INFO(channels << " channels");
    CHECK(EncodePng16(w, h, channels, data, "test") == OpenCvPng(bgr));
  }
}

TEST_CASE("JPEGs are OpenCV's bytes at every quality, shrunk or not", "[image_io]") {
  const Image8 image = TestImage(331, 203, 3, 3);
  for (const int quality : {1, 10, 50, 75, 90, 100}) {
    for (const int max_width : {1000, 160}) {
      double scale = 0.0;
      const std::string ours = EncodeJpegShrunk(image, max_width, quality, "test", &scale);
      cv::Mat bgr = AsBgrMat(image);
      double expected_scale = 1.0;
      if (image.width > max_width) {
        expected_scale = static_cast<double>(max_width) / image.width;
        cv::Mat shrunk;
        cv::resize(
            bgr, shrunk,
            cv::Size(max_width, static_cast<int>(std::lround(image.height * expected_scale))), 0, 0,
            cv::INTER_AREA);
        bgr = shrunk;
      }
      std::vector<std::uint8_t> buffer;
      REQUIRE(cv::imencode(".jpg", bgr, buffer,
                           {cv::IMWRITE_JPEG_QUALITY, quality, cv::IMWRITE_JPEG_OPTIMIZE, 1}));
      INFO("quality " << quality << ", width at most " << max_width);
      CHECK(ours == std::string(buffer.begin(), buffer.end()));
      CHECK(scale == expected_scale);
    }
  }
}

TEST_CASE("decoding gives what cv::imdecode gave, as RGB", "[image_io]") {
  std::vector<std::vector<std::uint8_t>> files;
  for (const int channels : {1, 3, 4}) {
    files.push_back(Bytes(OpenCvPng(AsBgrMat(TestImage(37, 21, channels, 9)))));
  }
  for (const int channels : {1, 3}) {
    std::vector<std::uint16_t> data(std::size_t(33) * 19 * channels);
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = static_cast<std::uint16_t>(i * 389);
    files.push_back(Bytes(EncodePng16(33, 19, channels, data, "t")));
  }
  // Grey of one bit and grey with alpha (OpenCV writes neither from these calls: libpng does).
  files.push_back(GreyPng(13, 9, 1, false));
  files.push_back(GreyPng(13, 9, 8, true));
  files.push_back(PalettePng(23, 11));
  for (std::size_t k = 0; k < files.size(); ++k) {
    INFO("file " << k);
    const Image8 ours = DecodedPngAsRgb(DecodePng(files[k], 4096, "test"));
    const Image8 theirs = OpenCvRgb(files[k]);
    CHECK(ours.width == theirs.width);
    CHECK(ours.height == theirs.height);
    CHECK(ours.data == theirs.data);
  }
}

TEST_CASE("decoding refuses what is not a PNG, a cut file and sides over the bound", "[image_io]") {
  const std::vector<std::uint8_t> good = Bytes(EncodePng(TestImage(40, 30, 3, 1), "t"));
  CHECK_THROWS_WITH(DecodePng(Bytes("not a png at all"), 100, "x.png"),
                    Catch::Contains("x.png: not a PNG image"));
  std::vector<std::uint8_t> cut(good.begin(), good.begin() + good.size() / 2);
  CHECK_THROWS_WITH(DecodePng(cut, 100, "x.png"),
                    Catch::Contains("x.png: not a readable PNG image"));
  CHECK_THROWS_WITH(DecodePng(good, 39, "x.png"), Catch::Contains("not a readable PNG image"));
  const DecodedPng ok = DecodePng(good, 40, "x.png");
  CHECK(ok.width == 40);
  CHECK(ok.height == 30);
  CHECK(ok.channels == 3);
  CHECK(ok.bit_depth == 8);
  std::vector<std::uint8_t> corrupt = good;
  corrupt[corrupt.size() / 2] ^= 0x55;  // inside the image data: its CRC no longer matches
  CHECK_THROWS_AS(DecodePng(corrupt, 100, "x.png"), std::invalid_argument);
}

}  // namespace corridorsim
