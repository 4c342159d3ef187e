#pragma once
// PNG encoding of the project's plain images (OpenCV stays out of public headers). Output is
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

}  // namespace corridorsim
