#include "render/noise.h"

#include "common/spec_checker.h"

#include <algorithm>
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

using Checker = SpecChecker;
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

// floor() without a library call (x86-64 without SSE4.1 has no rounding instruction).
int FloorToInt(double v) {
  const int t = static_cast<int>(v);
  return t > v ? t - 1 : t;
}

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
  }
  int operator()(std::uint32_t u) const {
    int shift = -reach_;  // counted without branches: the outcome is unpredictable
    for (const std::uint64_t t : thresholds_) shift += u >= t;
    return shift;
  }

 private:
  int reach_;
  std::vector<std::uint64_t> thresholds_;  // 2 reach entries
};

// Back-projection of pixel (u, v) at depth z with the pinhole part of the intrinsics.
struct BackProjector {
  double inv_fx, inv_fy, cx, cy;
  Eigen::Vector3d operator()(int u, int v, double z) const {
    return {z * (u - cx) * inv_fx, z * (v - cy) * inv_fy, z};
  }
};

// Cosine of the angle between the viewing ray of pixel (x, y) and the surface normal there, the
// normal from central differences of the back-projected depth (one-sided next to invalid pixels
// and the image border). 1 (head-on) where no normal can be estimated. `rows[d]` is row y + d.
double CosIncidence(const float* const* rows, int width, int height,
                    const BackProjector& back_project, int x, int y) {
  const Eigen::Vector3d p = back_project(x, y, rows[0][x]);
  auto neighbour = [&](int du, int dv, Eigen::Vector3d* q) {
    const int u = x + du, v = y + dv;
    if (u < 0 || u >= width || v < 0 || v >= height) return false;
    const float z = rows[dv][u];
    if (!(z > 0.0f)) return false;
    *q = back_project(u, v, z);
    return true;
  };
  auto tangent = [&](int du, int dv, Eigen::Vector3d* t) {
    Eigen::Vector3d before, after;
    const bool has_before = neighbour(-du, -dv, &before);
    const bool has_after = neighbour(du, dv, &after);
    if (has_before && has_after) {
      *t = after - before;
    } else if (has_after) {
      *t = after - p;
    } else if (has_before) {
      *t = p - before;
    } else {
      return false;
    }
    return true;
  };
  Eigen::Vector3d t_x, t_y;
  if (!tangent(1, 0, &t_x) || !tangent(0, 1, &t_y)) return 1.0;
  const Eigen::Vector3d normal = t_x.cross(t_y);
  const double norms = normal.norm() * p.norm();
  if (!(norms > 0.0)) return 1.0;
  return std::abs(normal.dot(p)) / norms;
}

}  // namespace

std::optional<SpecProblem> DepthNoiseOptions::Check() const {
  Checker c;
  c.NonNegative(min_m, "min_m");
  c.Require(max_m > min_m, "max_m", "must be greater than min_m (" + Num(min_m) + " m)");
  c.Positive(baseline_m, "baseline_m");
  c.Require(subpixel >= 1, "subpixel", "must be at least 1 (got " + std::to_string(subpixel) + ")");
  c.NonNegative(axial_a_m, "axial_a_m");
  c.NonNegative(axial_b, "axial_b");
  c.NonNegative(axial_z0_m, "axial_z0_m");
  c.Require(lateral_sigma_px >= 0 && lateral_sigma_px <= 10, "lateral_sigma_px",
            "must lie in [0, 10] px (got " + Num(lateral_sigma_px) + ")");
  c.Require(grazing_start_deg >= 0 && grazing_start_deg <= 90, "grazing_start_deg",
            "must lie in [0, 90] deg (got " + Num(grazing_start_deg) + ")");
  c.Require(grazing_max_deg >= grazing_start_deg && grazing_max_deg <= 90, "grazing_max_deg",
            "must lie in [grazing_start_deg, 90] deg (got " + Num(grazing_max_deg) + ")");
  c.Fraction(random_dropout, "random_dropout");
  c.InRange(max_m, 0.0, 1000.0, "max_m");
  c.InRange(baseline_m, 0.0, 10.0, "baseline_m");
  c.InRange(subpixel, 1, 1024, "subpixel");
  return c.problem();
}

void ParseDepthNoiseOptions(YamlMap& map, DepthNoiseOptions& o) {
  map.Read("min_m", o.min_m);
  map.Read("max_m", o.max_m);
  map.Read("quantise", o.quantise);
  map.Read("baseline_m", o.baseline_m);
  map.Read("subpixel", o.subpixel);
  map.Read("axial", o.axial);
  map.Read("axial_a_m", o.axial_a_m);
  map.Read("axial_b", o.axial_b);
  map.Read("axial_z0_m", o.axial_z0_m);
  map.Read("lateral_sigma_px", o.lateral_sigma_px);
  map.Read("grazing", o.grazing);
  map.Read("grazing_start_deg", o.grazing_start_deg);
  map.Read("grazing_max_deg", o.grazing_max_deg);
  map.Read("random_dropout", o.random_dropout);
  map.RejectUnknownKeys();
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
  std::vector<const float*> window(std::size_t(2 * halo + 1));  // rows y - halo .. y + halo
  const LateralShift lateral_shift(sigma_px > 0 ? sigma_px : 1.0, reach);
  const BackProjector back_project{1.0 / intrinsics.fx, 1.0 / intrinsics.fy, intrinsics.cx,
                                   intrinsics.cy};
  const double focal_baseline_steps = intrinsics.fx * options.baseline_m * options.subpixel;
  constexpr double kRadPerDeg = std::numbers::pi / 180;
  const double cos_start = std::cos(options.grazing_start_deg * kRadPerDeg);
  const double cos_max = std::cos(options.grazing_max_deg * kRadPerDeg);
  const double ramp_deg = options.grazing_max_deg - options.grazing_start_deg;

  for (int y = 0; y < height; ++y) {
    rows.Advance(y);
    for (int d = -halo; d <= halo; ++d) {
      window[std::size_t(d + halo)] = rows.Row(std::clamp(y + d, 0, height - 1));
    }
    const float* const* row_y = window.data() + halo;  // row_y[d] is row y + d
    float* out = &depth_m->at(0, y);
    for (int x = 0; x < width; ++x) {
      // 1. lateral: one 64-bit draw gives both shifts
      int sx = x, sy = y;
      if (reach > 0) {
        const std::uint64_t u = rng.NextU64();
        sx = std::clamp(x + lateral_shift(static_cast<std::uint32_t>(u)), 0, width - 1);
        sy = std::clamp(y + lateral_shift(static_cast<std::uint32_t>(u >> 32)), 0, height - 1);
      }
      double z = row_y[sy - y][sx];
      if (!(z > 0)) {
        out[x] = 0.0f;
        continue;
      }
      // 2. axial (Nguyen et al. 2012 eq. 6)
      if (options.axial) {
        const double dz = z - options.axial_z0_m;
        z += rng.Normal(0, options.axial_a_m + options.axial_b * dz * dz);
      }
      // 3. disparity quantisation to 1 / subpixel px
      if (options.quantise && z > 0) {
        const double steps = focal_baseline_steps / z + 0.5;
        // Beyond 2^31 steps z is far below any valid range (~1e-7 m) and stays as it is.
        const int disparity_steps = steps < 0x1.0p31 ? FloorToInt(steps) : -1;
        if (disparity_steps >= 0) {
          z = disparity_steps > 0 ? focal_baseline_steps / disparity_steps : 0.0;
        }
      }
      // 4. range
      if (!(z >= options.min_m && z <= options.max_m)) {
        out[x] = 0.0f;
        continue;
      }
      // 5. dropouts
      bool drop = false;
      if (options.grazing) {
        const double cos_theta =
            CosIncidence(row_y + (sy - y), width, height, back_project, sx, sy);
        if (cos_theta < cos_max) {
          drop = true;
        } else if (cos_theta < cos_start) {
          const double theta_deg = std::acos(cos_theta) / kRadPerDeg;
          drop = rng.Uniform01() * ramp_deg < theta_deg - options.grazing_start_deg;
        }
      }
      if (!drop && options.random_dropout > 0) drop = rng.Bernoulli(options.random_dropout);
      out[x] = drop ? 0.0f : static_cast<float>(z);
    }
  }
}

std::optional<SpecProblem> RgbNoiseOptions::Check() const {
  Checker c;
  c.Positive(exposure, "exposure");
  c.Fraction(vignetting, "vignetting");
  c.NonNegative(full_well_electrons, "full_well_electrons");
  c.NonNegative(read_noise_electrons, "read_noise_electrons");
  c.Require(read_noise_electrons == 0 || full_well_electrons > 0, "read_noise_electrons",
            "needs full_well_electrons > 0 to convert electrons to DN");
  c.NonNegative(motion_blur_px, "motion_blur_px");
  c.InRange(motion_blur_px, 0.0, 64.0, "motion_blur_px");
  c.InRange(exposure, 0.0, 100.0, "exposure");
  c.InRange(full_well_electrons, 0.0, 1e7, "full_well_electrons");
  c.InRange(read_noise_electrons, 0.0, 1e4, "read_noise_electrons");
  return c.problem();
}

void ParseRgbNoiseOptions(YamlMap& map, RgbNoiseOptions& o) {
  map.Read("exposure", o.exposure);
  map.Read("vignetting", o.vignetting);
  map.Read("full_well_electrons", o.full_well_electrons);
  map.Read("read_noise_electrons", o.read_noise_electrons);
  map.Read("motion_blur_px", o.motion_blur_px);
  map.RejectUnknownKeys();
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
            electrons += rng.Normal(0, options.read_noise_electrons);
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
