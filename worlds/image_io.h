#pragma once
// PNG and JPEG of the project's plain images, through libpng and libjpeg (OpenCV stays out of
// public headers; its imgcodecs module is not linked: image_io.cpp says why). Output is
// deterministic: fixed compression settings.

#include <cstdint>
#include <string>
#include <vector>

#include "common/image.h"

namespace corridorsim {

/// PNG bytes of an 8-bit image with 1, 3 (RGB) or 4 (RGBA) channels. Throws
/// std::invalid_argument naming `what` for an inconsistent image.
std::string EncodePng(const Image8& image, const std::string& what);

/// JPEG bytes (baseline, `quality` 1-100) of an 8-bit RGB image shrunk to at most `max_width`
/// pixels wide (area averaging; never enlarged), and the scale applied (kept / original size).
/// Deterministic for one build of libjpeg. Throws std::invalid_argument naming `what` for an
/// inconsistent image or arguments.
std::string EncodeJpegShrunk(const Image8& image, int max_width, int quality,
                             const std::string& what, double* scale);

/// PNG bytes of a 16-bit image, row-major, `channels` 1 or 3 (RGB order).
std::string EncodePng16(int width, int height, int channels, const std::vector<std::uint16_t>& data,
                        const std::string& what);

/// A PNG's samples as decoded: a palette expanded to RGB (RGBA where it has transparency), grey
/// of 1, 2 or 4 bits expanded to 8; otherwise as stored (1 grey, 2 grey + alpha, 3 RGB, 4 RGBA
/// channels, 8 or 16 bits).
struct DecodedPng {
  int width = 0;
  int height = 0;
  int channels = 0;
  int bit_depth = 8;                     // 8 or 16
  std::vector<std::uint8_t> samples8;    // bit_depth 8: width * height * channels
  std::vector<std::uint16_t> samples16;  // bit_depth 16: width * height * channels
};

/// Decodes PNG bytes. Throws std::invalid_argument naming `what` for bytes that are not a
/// readable PNG (libpng's reason in brackets) or a side over `max_side` pixels (refused from the
/// header, before any pixel is decoded).
DecodedPng DecodePng(const std::vector<std::uint8_t>& bytes, int max_side, const std::string& what);

/// The decoded image as 8-bit RGB: grey replicated, alpha dropped, 16 bits scaled to 8 (the
/// nearest of v / 257).
Image8 DecodedPngAsRgb(const DecodedPng& png);

}  // namespace corridorsim
