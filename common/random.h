#pragma once
// Seeded random streams with the project's own portable distributions (STYLE item 8).
//
// Every random source (world layout, odometry noise, each camera's noise, ...) draws from its own
// stream derived from (seed, run index, component name), so adding draws to one component never
// changes the numbers another sees. The generator is xoshiro256** seeded through SplitMix64; the
// distributions are written here because the standard library's differ between implementations.

#include <cmath>
#include <cstdint>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

namespace corridorsim {

/// 64-bit FNV-1a hash of a component name (stable across platforms and builds).
std::uint64_t HashName(std::string_view name);

namespace detail {
/// The ziggurat's layer edges x[i] and densities y[i] = exp(-x[i]^2 / 2) (see random.cpp).
struct ZigguratTables {
  static constexpr double kTailStart = 3.6541528853610088;  // r
  static constexpr double kArea = 4.92867323399e-3;         // v, area of each layer
  double x[257];
  double y[257];
};
ZigguratTables MakeZigguratTables();
/// Computed once before main(); no static initialiser draws from a RandomStream.
inline const ZigguratTables kZiggurat = MakeZigguratTables();
}  // namespace detail

class RandomStream {
 public:
  /// The stream of `component` (e.g. "worlds.layout") in run `run_index` of an experiment seeded
  /// with `seed`.
  RandomStream(std::uint64_t seed, std::uint64_t run_index, std::string_view component);

  /// A child stream, derived from this stream's identity (not its position) and `component`.
  RandomStream Derive(std::string_view component) const;

  /// Raw 64 random bits (xoshiro256**). Inline: per-pixel noise draws millions per frame.
  std::uint64_t NextU64() {
    const std::uint64_t result = Rotl(state_[1] * 5, 7) * 9;
    const std::uint64_t t = state_[1] << 17;
    state_[2] ^= state_[0];
    state_[3] ^= state_[1];
    state_[1] ^= state_[2];
    state_[0] ^= state_[3];
    state_[2] ^= t;
    state_[3] = Rotl(state_[3], 45);
    return result;
  }

  /// Uniform in [0, 1) with 53 random bits.
  double Uniform01() { return static_cast<double>(NextU64() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double Uniform(double lo, double hi);
  /// Uniform integer in [lo, hi] (inclusive), without modulo bias.
  std::int64_t UniformInt(std::int64_t lo, std::int64_t hi);
  /// Normal with the given mean and standard deviation (Marsaglia's polar method).
  double Normal(double mean = 0.0, double stddev = 1.0);
  /// Standard normal by the ziggurat method (Marsaglia and Tsang 2000, 256 layers): exact, one
  /// 64-bit draw per value 99 % of the time and no logarithm, several times faster than Normal();
  /// for per-pixel noise, where a frame takes hundreds of thousands of draws. Its sequence differs
  /// from Normal()'s. Inline: the common case is a table lookup and a comparison.
  double StandardNormalZiggurat() {
    const std::uint64_t bits = NextU64();
    const auto layer = static_cast<int>(bits & 0xFF);
    // A uniform in (-1, 1) from the top 53 bits (sign included), never exactly +-1.
    const double u = (static_cast<double>(bits >> 11) + 0.5) * 0x1.0p-52 - 1.0;
    const double x = u * detail::kZiggurat.x[layer];
    if (std::abs(x) < detail::kZiggurat.x[layer + 1]) return x;  // inside the core rectangle
    return ZigguratOutside(layer, u, x);
  }
  /// True with probability p.
  bool Bernoulli(double p);
  /// Exponential with the given rate (events per unit).
  double Exponential(double rate);
  /// Poisson with the given mean (>= 0): the multiplication method below a mean of 10, Hormann's
  /// transformed rejection with squeeze (PTRS, 1993) from 10 on. Both are exact.
  std::int64_t Poisson(double mean);
  /// Index drawn with probability proportional to `weights` (non-negative, positive sum).
  std::size_t Categorical(std::span<const double> weights);

  /// Fisher-Yates shuffle.
  template <class T>
  void Shuffle(std::vector<T>& values) {
    for (std::size_t i = values.size(); i > 1; --i) {
      const auto j = static_cast<std::size_t>(UniformInt(0, static_cast<std::int64_t>(i - 1)));
      std::swap(values[i - 1], values[j]);
    }
  }

 private:
  explicit RandomStream(std::uint64_t identity);
  // The rest of a ziggurat draw outside the core rectangle of `layer`: the tail, or the wedge
  // test and, when it rejects, a new draw.
  double ZigguratOutside(int layer, double u, double x);
  static constexpr std::uint64_t Rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

  std::uint64_t identity_;  // hash of (seed, run index, component path); seeds the state
  std::uint64_t state_[4];
  bool has_spare_normal_ = false;
  double spare_normal_ = 0.0;
};

}  // namespace corridorsim
