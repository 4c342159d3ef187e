#include "render/remap_kernel.h"

#include <cstring>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define CORRIDORSIM_REMAP_SSE41 1
#endif

namespace corridorsim::render::detail {
namespace {

// Where entry `e`'s bilinear block starts in its pass's colour (its second row `*stride` bytes
// further), or nullptr outside the model's valid angle, with the output pixel `rgb` set black.
inline const std::uint8_t* ColourBlock(const RemapEntry& e, std::span<const PassImages> passes,
                                       std::uint8_t* rgb, std::size_t* stride) {
  if (e.nearest == RemapEntry::kInvalid) {
    rgb[0] = rgb[1] = rgb[2] = 0;
    return nullptr;
  }
  const PassImages& pass = passes[e.pass];
  *stride = pass.width * 3;
  return pass.rgb + std::size_t(e.top_left) * 3;
}

#if defined(CORRIDORSIM_REMAP_SSE41)
// The two texels at p as 16-bit lanes r0 r1 g0 g1 b0 b1 . . (4-byte loads at p and p + 2).
__attribute__((target("sse4.1"))) inline __m128i TexelPair(const std::uint8_t* p) {
  std::int32_t first = 0, second = 0;
  std::memcpy(&first, p, 4);       // r0 g0 b0 r1
  std::memcpy(&second, p + 2, 4);  // b0 r1 g1 b1
  const __m128i p0 = _mm_cvtepu8_epi16(_mm_cvtsi32_si128(first));
  const __m128i p1 = _mm_srli_si128(_mm_cvtepu8_epi16(_mm_cvtsi32_si128(second)), 2);
  return _mm_unpacklo_epi16(p0, p1);
}

// One pixel per iteration in 128-bit lanes: the two texels of a row as 16-bit pairs, one
// multiply-add per row for the horizontal weights, then 32-bit multiplies for the vertical ones;
// the same integer sums as the scalar loop.
__attribute__((target("sse4.1"))) void BilinearRgbSse41(std::span<const RemapEntry> remap,
                                                        std::span<const PassImages> passes,
                                                        std::uint8_t* rgb) {
  const __m128i round = _mm_set1_epi32(32768);
  for (std::size_t i = 0; i < remap.size(); ++i, rgb += 3) {
    const RemapEntry e = remap[i];
    std::size_t stride = 0;
    const std::uint8_t* top_row = ColourBlock(e, passes, rgb, &stride);
    if (top_row == nullptr) continue;
    const __m128i weights_x = _mm_set1_epi32(int(std::uint32_t(e.wx) << 16 | (256u - e.wx)));
    const __m128i top = _mm_madd_epi16(TexelPair(top_row), weights_x);
    const __m128i bottom = _mm_madd_epi16(TexelPair(top_row + stride), weights_x);
    const __m128i sum = _mm_add_epi32(_mm_mullo_epi32(top, _mm_set1_epi32(256 - e.wy)),
                                      _mm_mullo_epi32(bottom, _mm_set1_epi32(e.wy)));
    const __m128i value = _mm_srli_epi32(_mm_add_epi32(sum, round), 16);
    const __m128i bytes = _mm_packus_epi16(_mm_packus_epi32(value, value), value);
    const auto packed = std::uint32_t(_mm_cvtsi128_si32(bytes));
    std::memcpy(rgb, &packed, 3);  // little-endian: r, g, b
  }
}

bool HaveSse41() {
  static const bool have = __builtin_cpu_supports("sse4.1");
  return have;
}
#endif

}  // namespace

void BilinearRgbScalar(std::span<const RemapEntry> remap, std::span<const PassImages> passes,
                       std::uint8_t* rgb) {
  for (std::size_t i = 0; i < remap.size(); ++i, rgb += 3) {
    const RemapEntry e = remap[i];
    std::size_t stride = 0;
    const std::uint8_t* a = ColourBlock(e, passes, rgb, &stride);
    if (a == nullptr) continue;
    const std::uint8_t* c = a + stride;
    const std::uint32_t wx = e.wx, wy = e.wy;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t top = a[k] * (256 - wx) + a[k + 3] * wx;
      const std::uint32_t bottom = c[k] * (256 - wx) + c[k + 3] * wx;
      rgb[k] = static_cast<std::uint8_t>((top * (256 - wy) + bottom * wy + 32768) >> 16);
    }
  }
}

void BilinearRgb(std::span<const RemapEntry> remap, std::span<const PassImages> passes,
                 std::uint8_t* rgb) {
#if defined(CORRIDORSIM_REMAP_SSE41)
  if (HaveSse41()) {
    BilinearRgbSse41(remap, passes, rgb);
    return;
  }
#endif
  BilinearRgbScalar(remap, passes, rgb);
}

void NearestLabels(std::span<const RemapEntry> remap, std::span<const PassImages> passes,
                   const float* depth_scale, std::uint32_t* instance, std::uint8_t* semantic,
                   float* depth) {
  for (std::size_t i = 0; i < remap.size(); ++i) {
    const RemapEntry e = remap[i];
    if (e.nearest == RemapEntry::kInvalid) {
      instance[i] = 0;
      semantic[i] = 0;
      if (depth != nullptr) depth[i] = 0.0f;
      continue;
    }
    const PassImages& pass = passes[e.pass];
    const std::size_t nearest = e.top_left + (e.nearest & 1u) + (e.nearest >> 1) * pass.width;
    instance[i] = pass.instance[nearest];
    semantic[i] = pass.semantic[nearest];
    if (depth != nullptr) depth[i] = pass.depth[nearest] * depth_scale[i];
  }
}

}  // namespace corridorsim::render::detail
