#pragma once
// Small statistics shared by the metric concerns: mean / RMSE / maximum of non-negative values,
// and the chi-square quantiles of the consistency bands.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>

#include <boost/math/distributions/chi_squared.hpp>

namespace corridorsim::metrics {

// Two-sided 95 % interval of the chi-square tests (NEES, NIS).
inline constexpr double kBandLowerTail = 0.025;
inline constexpr double kBandUpperTail = 0.975;

inline double ChiSquareQuantile(double dof, double p) {
  return boost::math::quantile(boost::math::chi_squared_distribution<double>(dof), p);
}

// Mean, RMSE and maximum of non-negative values (none when there are none).
struct Stats {
  std::size_t count = 0;
  double sum = 0.0;
  double sum_sq = 0.0;
  double max = 0.0;
  void Add(double v) {
    ++count;
    sum += v;
    sum_sq += v * v;
    max = std::max(max, v);
  }
  std::optional<double> mean() const {
    return count == 0 ? std::nullopt : std::optional(sum / static_cast<double>(count));
  }
  std::optional<double> rms() const {
    return count == 0 ? std::nullopt
                      : std::optional(std::sqrt(sum_sq / static_cast<double>(count)));
  }
  std::optional<double> maximum() const { return count == 0 ? std::nullopt : std::optional(max); }
};

}  // namespace corridorsim::metrics
