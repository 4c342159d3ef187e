#include "render/noise.h"

#include "common/io/options_yaml.h"
#include "common/options_checker.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace corridorsim::render {
namespace {

using Checker = OptionsChecker;
const auto& Num = FormatNumber;

// Clean copies of the rows [y - halo, y + halo] of an image that is overwritten in place, row by
// row from the top: the noise stages read the input around the pixel they write without copying
// the whole image. Advance(y) must be called before row y is overwritten.
template <class T>
class CleanRows {
 public:
  CleanRows(const T* image, int row_values, int height, int halo)
      : image_(image),
        row_values_(row_values),
        height_(height),
        halo_(halo),
        slots_(std::min(2 * halo + 1, height)),
        ring_(std::size_t(slots_) * row_values) {
    for (int r = 0; r < std::min(halo, height); ++r) Load(r);
  }
  void Advance(int y) {
    if (y + halo_ < height_) Load(y + halo_);
  }
  // Row r of the input; r must lie in [0, height) and within halo of the last Advance.
  const T* Row(int r) const { return &ring_[std::size_t(r % slots_) * row_values_]; }

 private:
  void Load(int r) {
    std::copy_n(image_ + std::size_t(r) * row_values_, row_values_,
                &ring_[std::size_t(r % slots_) * row_values_]);
  }

  const T* image_;
  int row_values_;
  int height_;
  int halo_;
  int slots_;
  std::vector<T> ring_;
};

// The lateral shift clamp(round(N(0, sigma)), -reach, reach) drawn by inversion: thresholds[i] is
// 2^32 P(shift <= i - reach), so one 32-bit uniform gives one shift (the distribution is the
// rounded Gaussian's, exactly up to the 2^-32 resolution of the thresholds).
class LateralShift {
 public:
  LateralShift(double sigma_px, int reach) : reach_(reach) {
    for (int k = -reach; k < reach; ++k) {
      const double cdf = 0.5 * std::erfc(-(k + 0.5) / (sigma_px * std::numbers::sqrt2));
      thresholds_.push_back(static_cast<std::uint64_t>(std::ldexp(cdf, 32)));
    }
    // Most of the 256 ranges of the top 8 bits hold no threshold: their shift is known.
    for (std::uint32_t b = 0; b < 256; ++b) {
      const std::uint64_t lo = std::uint64_t(b) << 24, hi = lo + (1u << 24) - 1;
      const int at_lo = Count(static_cast<std::uint32_t>(lo));
      by_top_byte_[b] = at_lo == Count(static_cast<std::uint32_t>(hi)) ? at_lo : kCount;
    }
  }
  int operator()(std::uint32_t u) const {
    const int shift = by_top_byte_[u >> 24];
    return shift != kCount ? shift : Count(u);
  }

 private:
  static constexpr int kCount = 1 << 30;  // a range with a threshold inside: count
  int Count(std::uint32_t u) const {
    int shift = -reach_;  // counted without branches: the outcome is unpredictable
    for (const std::uint64_t t : thresholds_) shift += u >= t;
    return shift;
  }

  int reach_;
  std::vector<std::uint64_t> thresholds_;  // 2 reach entries
  std::array<int, 256> by_top_byte_{};     // the shift for each top byte of u, or kCount
};

// Back-projection of pixel (u, v) at depth z with the pinhole part of the intrinsics.
struct BackProjector {
  double inv_fx, inv_fy, cx, cy;
  Eigen::Vector3d operator()(int u, int v, double z) const {
    return {z * (u - cx) * inv_fx, z * (v - cy) * inv_fy, z};
  }
};

// The incidence cosine at one pixel from its depth z and its neighbours' (0 = invalid); xs, ys
// its ray's x and y at z = 1 and inv_fx, inv_fy the ray steps between pixels. Single precision
// and without branches (a missing neighbour is replaced by the pixel itself, which makes the
// difference one-sided, or zero when both are missing), so a loop over it vectorises.
inline float CosIncidence(float z, float z_left, float z_right, float z_up, float z_down, float xs,
                          float ys, float inv_fx, float inv_fy) {
  // Back-projected neighbours P = z (xs, ys, 1), each replaced by the pixel where invalid.
  const bool l = z_left > 0, r = z_right > 0, u = z_up > 0, d = z_down > 0;
  const float zl = l ? z_left : z, xl = l ? xs - inv_fx : xs;
  const float zr = r ? z_right : z, xr = r ? xs + inv_fx : xs;
  const float zu = u ? z_up : z, yu = u ? ys - inv_fy : ys;
  const float zd = d ? z_down : z, yd = d ? ys + inv_fy : ys;
  const float tx0 = zr * xr - zl * xl, tx1 = (zr - zl) * ys, tx2 = zr - zl;
  const float ty0 = (zd - zu) * xs, ty1 = zd * yd - zu * yu, ty2 = zd - zu;
  const float n0 = tx1 * ty2 - tx2 * ty1, n1 = tx2 * ty0 - tx0 * ty2, n2 = tx0 * ty1 - tx1 * ty0;
  // The cosine does not depend on the length of the ray: use (xs, ys, 1).
  const float n_dot_p = n0 * xs + n1 * ys + n2;
  const float norms2 = (n0 * n0 + n1 * n1 + n2 * n2) * (xs * xs + ys * ys + 1.0f);
  const float cosine = std::abs(n_dot_p) / std::sqrt(std::max(norms2, 1e-30f));
  return ((z > 0) & (norms2 > 0)) ? cosine : 1.0f;  // & not &&: no branch, so it vectorises
}

// Cosines of the angle between the viewing ray and the surface normal for every pixel of row v,
// the normal from central differences of the back-projected depth (one-sided next to invalid
// pixels and the image border); 1 (head-on) where no normal can be estimated. `above` and
// `below` are rows v - 1 and v + 1, nullptr beyond the image.
void CosIncidenceRow(const float* above, const float* row, const float* below, int width, int v,
                     const BackProjector& back_project, float* out) {
  const auto inv_fx = static_cast<float>(back_project.inv_fx);
  const auto inv_fy = static_cast<float>(back_project.inv_fy);
  const auto cx = static_cast<float>(back_project.cx);
  const float ys = static_cast<float>((v - back_project.cy) * back_project.inv_fy);
  auto at = [&](int x) {
    return CosIncidence(row[x], x > 0 ? row[x - 1] : 0.0f, x + 1 < width ? row[x + 1] : 0.0f,
                        above != nullptr ? above[x] : 0.0f, below != nullptr ? below[x] : 0.0f,
                        (static_cast<float>(x) - cx) * inv_fx, ys, inv_fx, inv_fy);
  };
  if (above == nullptr || below == nullptr || width < 3) {
    for (int x = 0; x < width; ++x) out[x] = at(x);
    return;
  }
  // Inside the image every neighbour exists: a loop without conditional loads vectorises.
  out[0] = at(0);
  for (int x = 1; x + 1 < width; ++x) {
    out[x] = CosIncidence(row[x], row[x - 1], row[x + 1], above[x], below[x],
                          (static_cast<float>(x) - cx) * inv_fx, ys, inv_fx, inv_fy);
  }
  out[width - 1] = at(width - 1);
}

// theta in degrees for cosines in [lo, hi] (the grazing ramp), from a table with linear
// interpolation: within 1e-6 deg of acos over the default 70-78 deg ramp, without a libm call
// per pixel.
class AcosDegTable {
 public:
  AcosDegTable(double lo, double hi) : lo_(lo), step_((hi - lo) / kIntervals) {
    for (int i = 0; i <= kIntervals; ++i) {
      deg_[std::size_t(i)] = std::acos(lo + step_ * i) * 180.0 / std::numbers::pi;
    }
  }
  double operator()(double c) const {
    if (!(step_ > 0)) return std::acos(c) * 180.0 / std::numbers::pi;
    const double t = std::clamp((c - lo_) / step_, 0.0, double(kIntervals));
    const int i = std::min(static_cast<int>(t), kIntervals - 1);
    return deg_[std::size_t(i)] + (t - i) * (deg_[std::size_t(i) + 1] - deg_[std::size_t(i)]);
  }

 private:
  static constexpr int kIntervals = 4096;
  double lo_, step_;
  std::array<double, kIntervals + 1> deg_{};
};

}  // namespace

std::optional<OptionsProblem> DepthNoiseOptions::Check() const {
  if (auto problem = CheckOptionBounds(DepthNoiseOptionsTable(), *this)) return problem;
  Checker c;
  c.Require(max_m > min_m, "max_m",
            "must be greater than min_m (" + Num(min_m) + " m; got " + Num(max_m) + ")");
  c.Require(grazing_max_deg >= grazing_start_deg && grazing_max_deg <= 90, "grazing_max_deg",
            "must lie in [grazing_start_deg, 90] deg (got " + Num(grazing_max_deg) + ")");
  return c.problem();
}

void ParseDepthNoiseOptions(YamlMap& map, DepthNoiseOptions& options) {
  ReadOptions(map, DepthNoiseOptionsTable(), options);
}

void ApplyDepthNoise(const DepthNoiseOptions& options, const PinholeRadTan& intrinsics,
                     RandomStream& rng, ImageF* depth_m) {
  assert(depth_m != nullptr);
  assert(!options.Check());
  assert(intrinsics.width == depth_m->width && intrinsics.height == depth_m->height);
  const int width = depth_m->width, height = depth_m->height;
  if (width <= 0 || height <= 0) return;

  const double sigma_px = options.lateral_sigma_px;
  const int reach = sigma_px > 0 ? static_cast<int>(std::ceil(4 * sigma_px)) : 0;
  const int halo = reach + (options.grazing ? 1 : 0);
  CleanRows<float> rows(depth_m->data.data(), width, height, halo);
  std::vector<const float*> window(std::size_t(2 * reach + 1));  // rows y - reach .. y + reach
  const LateralShift lateral_shift(sigma_px > 0 ? sigma_px : 1.0, reach);
  const BackProjector back_project{1.0 / intrinsics.fx, 1.0 / intrinsics.fy, intrinsics.cx,
                                   intrinsics.cy};
  const double focal_baseline_steps = intrinsics.fx * options.baseline_m * options.subpixel;
  constexpr double kRadPerDeg = std::numbers::pi / 180;
  const double cos_start = std::cos(options.grazing_start_deg * kRadPerDeg);
  const double cos_max = std::cos(options.grazing_max_deg * kRadPerDeg);
  const double ramp_deg = options.grazing_max_deg - options.grazing_start_deg;
  const AcosDegTable theta_deg_of(cos_max, cos_start);

  // Incidence cosines of the noise-free input, a row at a time as the input rows arrive: a ring
  // of the rows y - reach .. y + reach (the sources the lateral shift can pick).
  const int cos_slots = std::min(2 * reach + 1, height);
  std::vector<float> cos_ring(options.grazing ? std::size_t(cos_slots) * width : 0);
  auto cos_row = [&](int r) { return &cos_ring[std::size_t(r % cos_slots) * width]; };
  auto compute_cos_row = [&](int r) {
    CosIncidenceRow(r > 0 ? rows.Row(r - 1) : nullptr, rows.Row(r),
                    r + 1 < height ? rows.Row(r + 1) : nullptr, width, r, back_project, cos_row(r));
  };
  std::vector<const float*> cos_window(window.size());
  std::vector<double> z_row(static_cast<std::size_t>(width));  // one row through the stages
  std::vector<float> cos_src(options.grazing ? std::size_t(width) : 0);

  for (int y = 0; y < height; ++y) {
    rows.Advance(y);
    if (options.grazing) {
      if (y == 0) {
        for (int r = 0; r <= std::min(reach, height - 1); ++r) compute_cos_row(r);
      } else if (y + reach < height) {
        compute_cos_row(y + reach);
      }
    }
    for (int d = -reach; d <= reach; ++d) {
      const int r = std::clamp(y + d, 0, height - 1);
      window[std::size_t(d + reach)] = rows.Row(r);
      if (options.grazing) cos_window[std::size_t(d + reach)] = cos_row(r);
    }
    const float* const* row_y = window.data() + reach;  // row_y[d] is row y + d
    const float* const* cos_y = cos_window.data() + reach;
    float* out = &depth_m->at(0, y);
    // Stage by stage over the row (the draws keep the per-pixel order of the stages' streams
    // within each stage): independent pixels pipeline, and the quantisation vectorises.
    // 1. lateral: one 64-bit draw gives both shifts; z and the incidence at the source pixel.
    for (int x = 0; x < width; ++x) {
      int sx = x, sy = y;
      if (reach > 0) {
        const std::uint64_t u = rng.NextU64();
        sx = std::clamp(x + lateral_shift(static_cast<std::uint32_t>(u)), 0, width - 1);
        sy = std::clamp(y + lateral_shift(static_cast<std::uint32_t>(u >> 32)), 0, height - 1);
      }
      z_row[std::size_t(x)] = row_y[sy - y][sx];
      if (options.grazing) cos_src[std::size_t(x)] = cos_y[sy - y][sx];
    }
    // 2. axial (Nguyen et al. 2012 eq. 6), on valid pixels only
    if (options.axial) {
      for (int x = 0; x < width; ++x) {
        double& z = z_row[std::size_t(x)];
        if (!(z > 0)) continue;
        const double dz = z - options.axial_z0_m;
        z += (options.axial_a_m + options.axial_b * dz * dz) * rng.StandardNormalZiggurat();
      }
    }
    // 3. disparity quantisation to 1 / subpixel px: d = floor(f b s / z + 1/2) steps, z = f b s / d
    // (d = 0: invalid). Steps are capped at 2^30 (z ~1e-7 m, far below any depth a camera can see).
    if (options.quantise) {
      for (int x = 0; x < width; ++x) {
        const double z = z_row[std::size_t(x)];
        const double steps = std::min(focal_baseline_steps / std::max(z, 1e-300) + 0.5, 0x1.0p30);
        const double d = static_cast<double>(static_cast<std::int32_t>(steps));  // floor: > 0
        z_row[std::size_t(x)] = z > 0 ? (d > 0 ? focal_baseline_steps / std::max(d, 1.0) : 0.0) : z;
      }
    }
    // 4. range, 5. grazing dropouts (decided on the noise-free surface at the source pixel), then
    // random dropouts.
    for (int x = 0; x < width; ++x) {
      const double z = z_row[std::size_t(x)];
      bool drop = !InDepthRange(options, z);
      if (!drop && options.grazing) {
        const double cos_theta = cos_src[std::size_t(x)];
        if (cos_theta < cos_max) {
          drop = true;
        } else if (cos_theta < cos_start) {
          const double theta_deg = theta_deg_of(cos_theta);
          drop = rng.Uniform01() * ramp_deg < theta_deg - options.grazing_start_deg;
        }
      }
      if (!drop && options.random_dropout > 0) drop = rng.Bernoulli(options.random_dropout);
      out[x] = drop ? 0.0f : static_cast<float>(z);
    }
  }
}

void ApplyDepthRange(const DepthNoiseOptions& options, ImageF* depth_m) {
  assert(depth_m != nullptr);
  for (float& z : depth_m->data) {
    if (!InDepthRange(options, z)) z = 0.0f;
  }
}

std::optional<OptionsProblem> RgbNoiseOptions::Check() const {
  if (auto problem = CheckOptionBounds(RgbNoiseOptionsTable(), *this)) return problem;
  Checker c;
  c.Require(read_noise_electrons == 0 || full_well_electrons > 0, "read_noise_electrons",
            "needs full_well_electrons > 0 to convert electrons to DN (got " +
                Num(read_noise_electrons) + " with full_well_electrons " +
                Num(full_well_electrons) + ")");
  return c.problem();
}

void ParseRgbNoiseOptions(YamlMap& map, RgbNoiseOptions& options) {
  ReadOptions(map, RgbNoiseOptionsTable(), options);
}

namespace {

// One tap of the motion blur kernel: offset in px and weight.
struct BlurTap {
  int dx, dy;
  float weight;
};

// A box of `length_px` along `direction` (unit), sampled every 1/4 px or finer with bilinear
// interpolation; taps at the same offset are merged. The weights sum to 1.
std::vector<BlurTap> BlurKernel(double length_px, const Eigen::Vector2d& direction) {
  const int samples = std::max(1, static_cast<int>(std::ceil(4 * length_px)));
  std::vector<BlurTap> taps;
  auto add = [&](int dx, int dy, double w) {
    if (w <= 0) return;
    for (BlurTap& t : taps) {
      if (t.dx == dx && t.dy == dy) {
        t.weight += static_cast<float>(w);
        return;
      }
    }
    taps.push_back({dx, dy, static_cast<float>(w)});
  };
  for (int i = 0; i < samples; ++i) {
    const double t = length_px * ((i + 0.5) / samples - 0.5);
    const double px = t * direction.x(), py = t * direction.y();
    const double x0 = std::floor(px), y0 = std::floor(py);
    const double fx = px - x0, fy = py - y0;
    const int ix = static_cast<int>(x0), iy = static_cast<int>(y0);
    add(ix, iy, (1 - fx) * (1 - fy) / samples);
    add(ix + 1, iy, fx * (1 - fy) / samples);
    add(ix, iy + 1, (1 - fx) * fy / samples);
    add(ix + 1, iy + 1, fx * fy / samples);
  }
  std::sort(taps.begin(), taps.end(), [](const BlurTap& a, const BlurTap& b) {
    return a.dy != b.dy ? a.dy < b.dy : a.dx < b.dx;
  });
  return taps;
}

}  // namespace

void ApplyRgbNoise(const RgbNoiseOptions& options, RandomStream& rng, Image8* rgb,
                   Eigen::Vector2d blur_direction) {
  assert(rgb != nullptr);
  assert(!options.Check());
  const int width = rgb->width, height = rgb->height, channels = rgb->channels;
  const double direction_norm = blur_direction.norm();
  const bool blur = options.motion_blur_px > 0 && direction_norm > 0;
  const bool shot = options.full_well_electrons > 0;
  if (width <= 0 || height <= 0 || channels <= 0) return;
  if (!blur && !shot && options.exposure == 1.0 && options.vignetting == 0.0) return;

  std::vector<BlurTap> taps;
  int halo = 0;
  if (blur) {
    taps = BlurKernel(options.motion_blur_px, blur_direction / direction_norm);
    for (const BlurTap& t : taps) halo = std::max(halo, std::abs(t.dy));
  }
  CleanRows<std::uint8_t> rows(rgb->data.data(), width * channels, height, halo);
  std::vector<float> signal(std::size_t(width) * channels);  // one row, DN before the noise

  // Vignetting gain 1 - v (r / r_corner)^2, r from the image centre.
  const double centre_x = 0.5 * (width - 1), centre_y = 0.5 * (height - 1);
  const double corner_r2 = centre_x * centre_x + centre_y * centre_y;
  const double vignetting_per_r2 = corner_r2 > 0 ? options.vignetting / corner_r2 : 0.0;
  const double electrons_per_dn = options.full_well_electrons / 255.0;
  const double dn_per_electron = shot ? 255.0 / options.full_well_electrons : 0.0;

  for (int y = 0; y < height; ++y) {
    rows.Advance(y);
    const std::uint8_t* in = rows.Row(y);
    if (blur) {
      // Tap by tap over the row: the inner loop is contiguous and vectorises.
      std::fill(signal.begin(), signal.end(), 0.0f);
      for (const BlurTap& tap : taps) {
        const std::uint8_t* src = rows.Row(std::clamp(y + tap.dy, 0, height - 1));
        const int x_begin = std::clamp(-tap.dx, 0, width),
                  x_end = std::clamp(width - tap.dx, 0, width);
        const std::ptrdiff_t shift = std::ptrdiff_t(tap.dx) * channels;
        for (std::size_t i = std::size_t(x_begin) * channels; i < std::size_t(x_end) * channels;
             ++i) {
          signal[i] += tap.weight * src[std::ptrdiff_t(i) + shift];
        }
        // Beyond the image border the border pixel repeats (x_begin <= x_end always).
        auto add_clamped = [&](int x) {
          const std::uint8_t* border =
              src + std::size_t(std::clamp(x + tap.dx, 0, width - 1)) * channels;
          for (int c = 0; c < channels; ++c) {
            signal[std::size_t(x) * channels + c] += tap.weight * border[c];
          }
        };
        for (int x = 0; x < x_begin; ++x) add_clamped(x);
        for (int x = x_end; x < width; ++x) add_clamped(x);
      }
    } else {
      std::copy_n(in, signal.size(), signal.begin());
    }
    std::uint8_t* out = rgb->Pixel(0, y);
    const double dy = y - centre_y;
    for (int x = 0; x < width; ++x) {
      const double dx = x - centre_x;
      const double gain = options.exposure * (1.0 - vignetting_per_r2 * (dx * dx + dy * dy));
      for (int c = 0; c < channels; ++c) {
        const std::size_t i = std::size_t(x) * channels + c;
        double dn = signal[i] * gain;
        if (shot) {
          double electrons = static_cast<double>(rng.Poisson(std::max(0.0, dn * electrons_per_dn)));
          if (options.read_noise_electrons > 0) {
            electrons += options.read_noise_electrons * rng.StandardNormalZiggurat();
          }
          dn = electrons * dn_per_electron;
        }
        // Round to the nearest DN and clamp: truncating dn + 0.5 >= 0 is its floor.
        out[i] = static_cast<std::uint8_t>(std::clamp(dn + 0.5, 0.0, 255.0));
      }
    }
  }
}

}  // namespace corridorsim::render
