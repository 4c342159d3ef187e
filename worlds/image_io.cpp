#include "worlds/image_io.h"

// PNG through libpng and JPEG through libjpeg(-turbo) directly, not OpenCV's imgcodecs: that
// module links GDAL, Poppler, HDF5 and a hundred more libraries on Debian 12, and loading them
// cost every corridorsim process about 180 ms of CPU before main() (measured 2026-12-07; the
// layers table of docs/architecture.md). The settings are the ones cv::imencode used, so the
// bytes are the same (tests/worlds/image_io_test.cpp compares them with OpenCV's).

#include <png.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include <jpeglib.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace corridorsim {
namespace {

// ---- PNG -----------------------------------------------------------------------------------

struct PngSink {
  std::string bytes;
};

void PngWrite(png_structp png, png_bytep data, png_size_t size) {
  auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
  sink->bytes.append(reinterpret_cast<const char*>(data), size);
}
void PngFlush(png_structp) {}

// libpng reports errors by longjmp to the setjmp of the function that called it: the functions
// between them hold no object with a destructor (libpng's own memory is freed by
// png_destroy_*_struct).
void PngError(png_structp png, png_const_charp message) {
  auto* text = static_cast<char*>(png_get_error_ptr(png));
  if (text != nullptr) std::snprintf(text, 200, "%s", message);
  png_longjmp(png, 1);
}
void PngWarning(png_structp, png_const_charp) {}

// Writes `rows` (each row `width * channels` samples of `depth` bits, 16-bit samples big-endian
// as PNG stores them) into sink. Returns false with `error` set when libpng failed. zlib level 1
// with the default strategy and libpng's default (adaptive) filters: what cv::imencode(".png",
// {IMWRITE_PNG_COMPRESSION, 1}) sets.
bool WritePngRows(int width, int height, int channels, int depth, png_bytep* rows, PngSink* sink,
                  char* error) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, error, PngError, PngWarning);
  if (png == nullptr) return false;
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png)) != 0) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_set_write_fn(png, sink, PngWrite, PngFlush);
  png_set_compression_level(png, 1);
  png_set_compression_strategy(png, Z_DEFAULT_STRATEGY);
  const int color_type = channels == 1   ? PNG_COLOR_TYPE_GRAY
                         : channels == 3 ? PNG_COLOR_TYPE_RGB
                                         : PNG_COLOR_TYPE_RGBA;
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), depth,
               color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, rows);
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  return true;
}

std::string EncodePngSamples(int width, int height, int channels, int depth,
                             std::vector<std::uint8_t>& samples, const std::string& what) {
  const std::size_t row_bytes = std::size_t(width) * channels * (depth / 8);
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) rows[y] = samples.data() + std::size_t(y) * row_bytes;
  PngSink sink;
  char error[200] = "libpng failed";
  if (!WritePngRows(width, height, channels, depth, rows.data(), &sink, error)) {
    throw std::runtime_error(what + ": PNG encoding failed (" + error + ")");
  }
  return std::move(sink.bytes);
}

struct PngSource {
  const std::uint8_t* data;
  std::size_t size;
  std::size_t at;
};

void PngRead(png_structp png, png_bytep out, png_size_t size) {
  auto* source = static_cast<PngSource*>(png_get_io_ptr(png));
  if (size > source->size - source->at) png_error(png, "the file ends inside the image");
  std::memcpy(out, source->data + source->at, size);
  source->at += size;
}

// The header's facts, and the decoded rows into `pixels` (sized here before any row is read).
struct PngLayout {
  png_uint_32 width = 0, height = 0;
  int channels = 0, depth = 0;
};

bool ReadPngRows(PngSource* source, int max_side, std::vector<std::uint8_t>* pixels,
                 std::vector<png_bytep>* rows, PngLayout* layout, char* error) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, error, PngError, PngWarning);
  if (png == nullptr) return false;
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    return false;
  }
  if (setjmp(png_jmpbuf(png)) != 0) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_set_read_fn(png, source, PngRead);
  png_set_user_limits(png, static_cast<png_uint_32>(max_side), static_cast<png_uint_32>(max_side));
  png_read_info(png, info);
  const int color_type = png_get_color_type(png, info);
  const int bit_depth = png_get_bit_depth(png, info);
  // What cv::imdecode(IMREAD_UNCHANGED) gives: a palette as RGB (RGBA with transparency), grey
  // below 8 bits as 8-bit grey, everything else as stored.
  if (color_type == PNG_COLOR_TYPE_PALETTE) {
    png_set_palette_to_rgb(png);
    if (png_get_valid(png, info, PNG_INFO_tRNS) != 0) png_set_tRNS_to_alpha(png);
  }
  if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  png_set_interlace_handling(png);
  png_read_update_info(png, info);
  layout->width = png_get_image_width(png, info);
  layout->height = png_get_image_height(png, info);
  layout->channels = png_get_channels(png, info);
  layout->depth = png_get_bit_depth(png, info);
  const std::size_t row_bytes = png_get_rowbytes(png, info);
  pixels->assign(row_bytes * layout->height, 0);
  rows->resize(layout->height);
  for (png_uint_32 y = 0; y < layout->height; ++y) (*rows)[y] = pixels->data() + y * row_bytes;
  png_read_image(png, rows->data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

// ---- JPEG ----------------------------------------------------------------------------------

struct JpegErrorManager {
  jpeg_error_mgr base;
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
};

void JpegErrorExit(j_common_ptr cinfo) {
  auto* manager = reinterpret_cast<JpegErrorManager*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, manager->message);
  std::longjmp(manager->jump, 1);
}
void JpegOutputMessage(j_common_ptr) {}

// Baseline JPEG of RGB rows at `quality`, Huffman tables optimised: what cv::imencode(".jpg",
// {IMWRITE_JPEG_QUALITY, q, IMWRITE_JPEG_OPTIMIZE, 1}) sets (libjpeg's defaults otherwise:
// JFIF header, 4:2:0 chroma, no restart markers).
bool WriteJpeg(int width, int height, int quality, JSAMPROW* rows, unsigned char** out,
               unsigned long* out_size, char* error) {
  jpeg_compress_struct cinfo;
  JpegErrorManager manager;
  cinfo.err = jpeg_std_error(&manager.base);
  manager.base.error_exit = JpegErrorExit;
  manager.base.output_message = JpegOutputMessage;
  if (setjmp(manager.jump) != 0) {
    std::snprintf(error, 200, "%s", manager.message);
    jpeg_destroy_compress(&cinfo);
    return false;
  }
  jpeg_create_compress(&cinfo);
  jpeg_mem_dest(&cinfo, out, out_size);
  cinfo.image_width = static_cast<JDIMENSION>(width);
  cinfo.image_height = static_cast<JDIMENSION>(height);
  cinfo.input_components = 3;
  cinfo.in_color_space = JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, quality, TRUE);
  cinfo.optimize_coding = TRUE;
  jpeg_start_compress(&cinfo, TRUE);
  jpeg_write_scanlines(&cinfo, rows, static_cast<JDIMENSION>(height));
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  return true;
}

bool ConsistentImage(const Image8& image) {
  return image.width > 0 && image.height > 0 &&
         image.data.size() == std::size_t(image.width) * image.height * image.channels;
}

}  // namespace

std::string EncodePng(const Image8& image, const std::string& what) {
  const bool valid =
      (image.channels == 1 || image.channels == 3 || image.channels == 4) && ConsistentImage(image);
  if (!valid) throw std::invalid_argument(what + ": image has inconsistent size or channels");
  std::vector<std::uint8_t> samples = image.data;
  return EncodePngSamples(image.width, image.height, image.channels, 8, samples, what);
}

std::string EncodeJpegShrunk(const Image8& image, int max_width, int quality,
                             const std::string& what, double* scale) {
  if (image.channels != 3 || !ConsistentImage(image)) {
    throw std::invalid_argument(what + ": not an RGB image of consistent size");
  }
  if (max_width < 1 || quality < 1 || quality > 100) {
    throw std::invalid_argument(what + ": JPEG width or quality out of range");
  }
  cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<std::uint8_t*>(image.data.data()));
  double s = 1.0;
  if (image.width > max_width) {
    // Area averaging treats each channel alike: shrinking RGB gives what shrinking BGR gave.
    s = static_cast<double>(max_width) / image.width;
    const int height = std::max(1, static_cast<int>(std::lround(image.height * s)));
    cv::Mat shrunk;
    cv::resize(rgb, shrunk, cv::Size(max_width, height), 0, 0, cv::INTER_AREA);
    rgb = shrunk;
  }
  std::vector<JSAMPROW> rows(static_cast<std::size_t>(rgb.rows));
  for (int y = 0; y < rgb.rows; ++y) rows[y] = rgb.ptr<std::uint8_t>(y);
  unsigned char* out = nullptr;
  unsigned long out_size = 0;
  char error[200] = "libjpeg failed";
  const bool written = WriteJpeg(rgb.cols, rgb.rows, quality, rows.data(), &out, &out_size, error);
  std::string bytes;
  if (written && out != nullptr) bytes.assign(reinterpret_cast<const char*>(out), out_size);
  std::free(out);  // jpeg_mem_dest's buffer (malloc'ed by libjpeg), also after a failure
  if (!written) throw std::runtime_error(what + ": JPEG encoding failed (" + error + ")");
  if (scale != nullptr) *scale = s;
  return bytes;
}

std::string EncodePng16(int width, int height, int channels, const std::vector<std::uint16_t>& data,
                        const std::string& what) {
  if (width <= 0 || height <= 0 || (channels != 1 && channels != 3) ||
      data.size() != std::size_t(width) * height * channels) {
    throw std::invalid_argument(what + ": 16-bit image has inconsistent size or channels");
  }
  std::vector<std::uint8_t> samples(data.size() * 2);
  for (std::size_t i = 0; i < data.size(); ++i) {  // PNG stores 16-bit samples big-endian
    samples[2 * i] = static_cast<std::uint8_t>(data[i] >> 8);
    samples[2 * i + 1] = static_cast<std::uint8_t>(data[i] & 0xff);
  }
  return EncodePngSamples(width, height, channels, 16, samples, what);
}

DecodedPng DecodePng(const std::vector<std::uint8_t>& bytes, int max_side,
                     const std::string& what) {
  if (max_side < 1) throw std::invalid_argument(what + ": the largest side must be positive");
  PngSource source{bytes.data(), bytes.size(), 0};
  std::vector<std::uint8_t> pixels;
  std::vector<png_bytep> rows;
  PngLayout layout;
  char error[200] = "libpng failed";
  if (bytes.size() < 8 || png_sig_cmp(bytes.data(), 0, 8) != 0) {
    throw std::invalid_argument(what + ": not a PNG image");
  }
  if (!ReadPngRows(&source, max_side, &pixels, &rows, &layout, error)) {
    throw std::invalid_argument(what + ": not a readable PNG image (" + error + ")");
  }
  DecodedPng image;
  image.width = static_cast<int>(layout.width);
  image.height = static_cast<int>(layout.height);
  image.channels = layout.channels;
  image.bit_depth = layout.depth;
  if (layout.depth == 16) {
    image.samples16.resize(pixels.size() / 2);
    for (std::size_t i = 0; i < image.samples16.size(); ++i) {
      image.samples16[i] = static_cast<std::uint16_t>((pixels[2 * i] << 8) | pixels[2 * i + 1]);
    }
  } else {
    image.samples8 = std::move(pixels);
  }
  return image;
}

Image8 DecodedPngAsRgb(const DecodedPng& png) {
  Image8 rgb(png.width, png.height, 3);
  const std::size_t count = std::size_t(png.width) * png.height;
  const int channels = png.channels;
  // 16 bits to 8 as cv::Mat::convertTo(CV_8U, 1 / 257.0) did: the nearest value (no ties: v / 257
  // never ends in exactly .5).
  const auto sample = [&](std::size_t i) -> std::uint8_t {
    if (png.bit_depth == 16) {
      return static_cast<std::uint8_t>(std::lround(png.samples16[i] / 257.0));
    }
    return png.samples8[i];
  };
  for (std::size_t p = 0; p < count; ++p) {
    std::uint8_t* out = &rgb.data[p * 3];
    const std::size_t in = p * channels;
    if (channels <= 2) {  // grey (alpha dropped): replicated
      out[0] = out[1] = out[2] = sample(in);
    } else {  // RGB (alpha dropped)
      out[0] = sample(in);
      out[1] = sample(in + 1);
      out[2] = sample(in + 2);
    }
  }
  return rgb;
}

}  // namespace corridorsim
