#include "harness/study/study_stats.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

#include "common/random.h"

namespace corridorsim::study {
namespace {

Interval PercentileInterval(std::vector<double> estimates) {
  const double tail = (1.0 - kConfidenceLevel) / 2.0;
  return {Quantile(estimates, tail), Quantile(std::move(estimates), 1.0 - tail)};
}

double NormalUpperTail(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

}  // namespace

double Quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double h = (static_cast<double>(values.size()) - 1.0) * std::clamp(q, 0.0, 1.0);
  const auto below = static_cast<std::size_t>(std::floor(h));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  return values[below] + (h - static_cast<double>(below)) * (values[above] - values[below]);
}

Interval BootstrapMeanInterval(const std::vector<double>& values, std::string_view stream) {
  if (values.size() == 1) return {values[0], values[0]};
  RandomStream rng(0, 0, "study.bootstrap." + std::string(stream));
  const auto n = static_cast<std::int64_t>(values.size());
  std::vector<double> means(kBootstrapResamples);
  for (double& mean : means) {
    double sum = 0.0;
    for (std::int64_t i = 0; i < n; ++i) sum += values[rng.UniformInt(0, n - 1)];
    mean = sum / static_cast<double>(n);
  }
  return PercentileInterval(std::move(means));
}

PairedIntervals BootstrapPairedIntervals(const std::vector<double>& a, const std::vector<double>& b,
                                         std::string_view stream) {
  PairedIntervals out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (a.size() == 1) {
    out.diff = {a[0] - b[0], a[0] - b[0]};
    out.ratio = b[0] != 0.0 ? Interval{a[0] / b[0], a[0] / b[0]} : Interval{nan, nan};
    return out;
  }
  RandomStream rng(0, 0, "study.bootstrap." + std::string(stream));
  const auto n = static_cast<std::int64_t>(a.size());
  std::vector<double> diffs(kBootstrapResamples), ratios(kBootstrapResamples);
  bool ratio_defined = true;
  for (int r = 0; r < kBootstrapResamples; ++r) {
    double sa = 0.0, sb = 0.0;
    for (std::int64_t i = 0; i < n; ++i) {
      const std::int64_t k = rng.UniformInt(0, n - 1);
      sa += a[k];
      sb += b[k];
    }
    diffs[r] = (sa - sb) / static_cast<double>(n);
    if (sb == 0.0) ratio_defined = false;
    ratios[r] = sb != 0.0 ? sa / sb : 0.0;
  }
  out.diff = PercentileInterval(std::move(diffs));
  out.ratio = ratio_defined ? PercentileInterval(std::move(ratios)) : Interval{nan, nan};
  return out;
}

double SignTestP(const std::vector<double>& differences) {
  int positive = 0, n = 0;
  for (double d : differences) {
    if (d == 0.0) continue;
    ++n;
    positive += d > 0.0;
  }
  if (n == 0) return 1.0;
  // P(X <= min(k, n - k)) for X ~ Binomial(n, 1/2), doubled; summed in logs (n up to 100000).
  const int k = std::min(positive, n - positive);
  double tail = 0.0;
  for (int i = 0; i <= k; ++i) {
    const double log_term =
        std::lgamma(n + 1.0) - std::lgamma(i + 1.0) - std::lgamma(n - i + 1.0) - n * std::log(2.0);
    tail += std::exp(log_term);
  }
  return std::min(1.0, 2.0 * tail);
}

double WilcoxonSignedRankP(const std::vector<double>& differences) {
  std::vector<double> d;
  for (double v : differences) {
    if (v != 0.0) d.push_back(v);
  }
  const std::size_t n = d.size();
  if (n == 0) return 1.0;
  // Ranks of |d| with ties at their average rank.
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t i, std::size_t j) { return std::abs(d[i]) < std::abs(d[j]); });
  std::vector<double> rank(n);
  bool ties = false;
  double tie_term = 0.0;  // sum of (t^3 - t) over tie groups
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i;
    while (j + 1 < n && std::abs(d[order[j + 1]]) == std::abs(d[order[i]])) ++j;
    const double average = (static_cast<double>(i + j) + 2.0) / 2.0;
    for (std::size_t k = i; k <= j; ++k) rank[order[k]] = average;
    const double t = static_cast<double>(j - i + 1);
    if (j > i) {
      ties = true;
      tie_term += t * t * t - t;
    }
    i = j + 1;
  }
  double w_plus = 0.0;
  for (std::size_t i = 0; i < n; ++i) w_plus += d[i] > 0.0 ? rank[i] : 0.0;
  const double nd = static_cast<double>(n);
  const double mean = nd * (nd + 1.0) / 4.0;
  if (!ties && n <= 50) {
    // Exact: the number of subsets of {1..n} with each sum, over 2^n.
    const auto max_sum = static_cast<std::size_t>(n * (n + 1) / 2);
    std::vector<double> count(max_sum + 1, 0.0);
    count[0] = 1.0;
    for (std::size_t r = 1; r <= n; ++r) {
      for (std::size_t s = max_sum; s >= r; --s) count[s] += count[s - r];
    }
    const auto w =
        static_cast<std::size_t>(std::llround(std::min(w_plus, nd * (nd + 1.0) / 2.0 - w_plus)));
    double tail = 0.0;
    for (std::size_t s = 0; s <= w; ++s) tail += count[s];
    return std::min(1.0, 2.0 * tail / std::pow(2.0, nd));
  }
  const double variance = nd * (nd + 1.0) * (2.0 * nd + 1.0) / 24.0 - tie_term / 48.0;
  if (variance <= 0.0) return 1.0;
  const double z = std::max(0.0, std::abs(w_plus - mean) - 0.5) / std::sqrt(variance);
  return std::min(1.0, 2.0 * NormalUpperTail(z));
}

}  // namespace corridorsim::study
