#include "common/random.h"

#include <cassert>
#include <cmath>
#include <limits>

namespace corridorsim {
namespace {

std::uint64_t SplitMix64(std::uint64_t& x) {
  x += 0x9E3779B97F4A7C15ULL;
  std::uint64_t z = x;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

std::uint64_t Combine(std::uint64_t a, std::uint64_t b) {
  std::uint64_t x = a ^ (b + 0x9E3779B97F4A7C15ULL + (a << 6) + (a >> 2));
  return SplitMix64(x);
}

// log(k!) for k >= 0: exact table below 10, Stirling's series (relative error < 1e-15) from 10 on.
// Written here rather than std::lgamma, which may write the global `signgam` and so is not
// thread-safe.
double LogFactorial(std::int64_t k) {
  static constexpr double kTable[10] = {0.0,
                                        0.0,
                                        0.6931471805599453,
                                        1.791759469228055,
                                        3.1780538303479458,
                                        4.787491742782046,
                                        6.579251212010101,
                                        8.525161361065415,
                                        10.60460290274525,
                                        12.801827480081469};
  if (k < 10) return kTable[k];
  const double n = static_cast<double>(k) + 1.0;  // log(k!) = lgamma(n)
  const double inv = 1.0 / n, inv2 = inv * inv;
  // lgamma(n) = (n - 1/2) log n - n + log(2 pi) / 2
  //             + 1/(12 n) - 1/(360 n^3) + 1/(1260 n^5) - 1/(1680 n^7) + 1/(1188 n^9) - ...
  const double series =
      inv *
      (1.0 / 12 + inv2 * (-1.0 / 360 + inv2 * (1.0 / 1260 + inv2 * (-1.0 / 1680 + inv2 / 1188))));
  return (n - 0.5) * std::log(n) - n + 0.91893853320467274 + series;
}

}  // namespace

std::uint64_t HashName(std::string_view name) {
  std::uint64_t h = 0xCBF29CE484222325ULL;
  for (const char c : name) {
    h ^= static_cast<std::uint8_t>(c);
    h *= 0x100000001B3ULL;
  }
  return h;
}

RandomStream::RandomStream(std::uint64_t seed, std::uint64_t run_index, std::string_view component)
    : RandomStream(Combine(Combine(seed, run_index), HashName(component))) {}

RandomStream::RandomStream(std::uint64_t identity) : identity_(identity) {
  std::uint64_t x = identity;
  for (auto& s : state_) s = SplitMix64(x);
}

RandomStream RandomStream::Derive(std::string_view component) const {
  return RandomStream(Combine(identity_, HashName(component)));
}

double RandomStream::Uniform(double lo, double hi) { return lo + (hi - lo) * Uniform01(); }

std::int64_t RandomStream::UniformInt(std::int64_t lo, std::int64_t hi) {
  assert(lo <= hi);
  const std::uint64_t range = static_cast<std::uint64_t>(hi) - static_cast<std::uint64_t>(lo) + 1;
  if (range == 0) return static_cast<std::int64_t>(NextU64());  // the full 64-bit range
  // Reject the top partial block so every value is equally likely.
  const std::uint64_t limit =
      std::numeric_limits<std::uint64_t>::max() - std::numeric_limits<std::uint64_t>::max() % range;
  std::uint64_t x = NextU64();
  while (x >= limit) x = NextU64();
  return static_cast<std::int64_t>(static_cast<std::uint64_t>(lo) + x % range);
}

double RandomStream::Normal(double mean, double stddev) {
  if (has_spare_normal_) {
    has_spare_normal_ = false;
    return mean + stddev * spare_normal_;
  }
  double u = 0.0, v = 0.0, s = 0.0;
  do {
    u = 2.0 * Uniform01() - 1.0;
    v = 2.0 * Uniform01() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double factor = std::sqrt(-2.0 * std::log(s) / s);
  spare_normal_ = v * factor;
  has_spare_normal_ = true;
  return mean + stddev * u * factor;
}

// Ziggurat of the unnormalised density f(x) = exp(-x^2 / 2) in 256 layers of equal area kArea
// (Marsaglia and Tsang 2000): x[0] = kArea / f(r) is the width of the base layer (the strip below
// f(r) plus the tail beyond r, as a rectangle of the same area), x[1] = r, x[i + 1] solves
// f(x[i + 1]) = f(x[i]) + kArea / x[i], x[256] = 0; y[i] = f(x[i]).
detail::ZigguratTables detail::MakeZigguratTables() {
  ZigguratTables t{};
  auto f = [](double v) { return std::exp(-0.5 * v * v); };
  t.x[0] = ZigguratTables::kArea / f(ZigguratTables::kTailStart);
  t.x[1] = ZigguratTables::kTailStart;
  for (int i = 1; i < 255; ++i) {
    t.x[i + 1] = std::sqrt(-2.0 * std::log(ZigguratTables::kArea / t.x[i] + f(t.x[i])));
  }
  t.x[256] = 0.0;
  for (int i = 0; i < 257; ++i) t.y[i] = f(t.x[i]);
  return t;
}

double RandomStream::ZigguratOutside(int layer, double u, double x) {
  if (layer == 0) {
    // The tail beyond r (Marsaglia 1964): x = -log(U1) / r accepted when -2 log(U2) > x^2.
    constexpr double r = detail::ZigguratTables::kTailStart;
    double tail = 0.0, y = 0.0;
    do {
      tail = -std::log1p(-Uniform01()) / r;
      y = -std::log1p(-Uniform01());
    } while (2.0 * y < tail * tail);
    return u < 0 ? -(r + tail) : r + tail;
  }
  // The wedge between the core rectangle and the curve: accept under the density, else draw
  // anew (about 1 % of draws; the recursion is as deep as the rejections in a row).
  const detail::ZigguratTables& t = detail::kZiggurat;
  const double height = t.y[layer] + Uniform01() * (t.y[layer + 1] - t.y[layer]);
  return height < std::exp(-0.5 * x * x) ? x : StandardNormalZiggurat();
}

bool RandomStream::Bernoulli(double p) { return Uniform01() < p; }

double RandomStream::Exponential(double rate) { return -std::log1p(-Uniform01()) / rate; }

std::int64_t RandomStream::Poisson(double mean) {
  assert(mean >= 0.0 && mean < 1e15);  // far below the int64 range
  if (mean < 10.0) {
    // Multiplication method: the number of uniforms whose running product stays above e^-mean.
    const double limit = std::exp(-mean);
    std::int64_t k = 0;
    double product = Uniform01();
    while (product > limit) {
      ++k;
      product *= Uniform01();
    }
    return k;
  }
  // PTRS: W. Hormann, "The transformed rejection method for generating Poisson random variables",
  // Insurance: Mathematics and Economics 12 (1993), constants of Table 1 / algorithm PTRS.
  const double sqrt_mean = std::sqrt(mean);
  const double b = 0.931 + 2.53 * sqrt_mean;
  const double a = -0.059 + 0.02483 * b;
  const double v_r = 0.9277 - 3.6224 / (b - 2.0);
  for (;;) {
    const double u = Uniform01() - 0.5;
    const double v = Uniform01();
    const double us = 0.5 - std::fabs(u);
    if (us <= 0.0) continue;  // u = -0.5 maps to -infinity
    const double kf = std::floor((2.0 * a / us + b) * u + mean + 0.43);
    if (us >= 0.07 && v <= v_r) return static_cast<std::int64_t>(kf);  // squeeze: accept at once
    if (kf < 0.0 || (us < 0.013 && v > us)) continue;
    const auto k = static_cast<std::int64_t>(kf);
    const double inv_alpha = 1.1239 + 1.1328 / (b - 3.4);
    if (std::log(v * inv_alpha / (a / (us * us) + b)) <=
        -mean + kf * std::log(mean) - LogFactorial(k)) {
      return k;
    }
  }
}

std::size_t RandomStream::Categorical(std::span<const double> weights) {
  assert(!weights.empty());
  double total = 0.0;
  for (const double w : weights) total += w;
  assert(total > 0.0);
  const double target = Uniform01() * total;
  double cumulative = 0.0;
  for (std::size_t i = 0; i < weights.size(); ++i) {
    cumulative += weights[i];
    if (target < cumulative) return i;
  }
  // Rounding can leave target == total: return the last index with positive weight.
  for (std::size_t i = weights.size(); i-- > 0;) {
    if (weights[i] > 0.0) return i;
  }
  return weights.size() - 1;
}

}  // namespace corridorsim
