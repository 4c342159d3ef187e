#pragma once
// Plain image buffers shared by worlds (textures), render (frames) and slam (inputs).

#include <cstdint>
#include <vector>

namespace corridorsim {

/// Row-major interleaved 8-bit image; row 0 is the top row. Channels are RGB(A) order.
struct Image8 {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<std::uint8_t> data;  // width * height * channels bytes

  Image8() = default;
  Image8(int w, int h, int c) : width(w), height(h), channels(c), data(std::size_t(w) * h * c, 0) {}

  std::uint8_t* Pixel(int x, int y) { return &data[(std::size_t(y) * width + x) * channels]; }
  const std::uint8_t* Pixel(int x, int y) const {
    return &data[(std::size_t(y) * width + x) * channels];
  }
  bool empty() const { return data.empty(); }
};

/// Row-major single-channel float image (depth in metres, or other per-pixel quantities).
struct ImageF {
  int width = 0;
  int height = 0;
  std::vector<float> data;  // width * height values

  ImageF() = default;
  ImageF(int w, int h, float fill = 0.0f) : width(w), height(h), data(std::size_t(w) * h, fill) {}

  float& at(int x, int y) { return data[std::size_t(y) * width + x]; }
  float at(int x, int y) const { return data[std::size_t(y) * width + x]; }
};

}  // namespace corridorsim
