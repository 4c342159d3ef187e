#pragma once
// The per-pixel loops of a camera's remap (CameraRenderer::Compose): bilinear colour from the
// pass images through a precomputed table, and nearest labels and depth. Exposed for tests.

#include <cstddef>
#include <cstdint>
#include <span>

namespace corridorsim::render::detail {

/// What the remap reads per output pixel, 8 bytes: bilinear colour from the 2x2 block at
/// `top_left` with 8-bit fixed-point weights (a weight of 256 is stored as the next block with
/// weight 0), nearest labels and depth at top_left + the offsets in `nearest`.
struct RemapEntry {
  std::uint32_t top_left = 0;   // pass pixel index of the bilinear block
  std::uint8_t wx = 0, wy = 0;  // weights of the right column / bottom row, in 1/256
  std::uint8_t pass = 0;
  std::uint8_t nearest = kInvalid;  // bit 0: right column, bit 1: bottom row; kInvalid: none
  static constexpr std::uint8_t kInvalid = 0x80;
};

/// One pass's images as the remap reads them (row-major, `width` pixels a row).
struct PassImages {
  const std::uint8_t* rgb = nullptr;  // 3 bytes a pixel
  const std::uint32_t* instance = nullptr;
  const std::uint8_t* semantic = nullptr;
  const float* depth = nullptr;  // null without depth
  std::size_t width = 0;
};

/// rgb[3 i..3 i + 2] = the bilinear blend of entry i's block (exact integer arithmetic: the
/// rounded sum of the four weighted texels), 0 for invalid entries. Uses SSE4.1 where the CPU
/// has it; the result is the same bytes either way.
void BilinearRgb(std::span<const RemapEntry> remap, std::span<const PassImages> passes,
                 std::uint8_t* rgb);
/// The same in plain C++ (the reference the vector path is tested against).
void BilinearRgbScalar(std::span<const RemapEntry> remap, std::span<const PassImages> passes,
                       std::uint8_t* rgb);
/// Nearest instance, class and (scaled by depth_scale[i]) depth of each entry, 0 where invalid.
/// `depth` and `depth_scale` may be null together.
void NearestLabels(std::span<const RemapEntry> remap, std::span<const PassImages> passes,
                   const float* depth_scale, std::uint32_t* instance, std::uint8_t* semantic,
                   float* depth);

}  // namespace corridorsim::render::detail
