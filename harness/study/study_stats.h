#pragma once
// The statistics of a study's summary (docs/studies.md, "The summary"): sample quantiles,
// percentile-bootstrap confidence intervals from a seeded stream (so a summary is the same bytes
// on every machine and for every number of workers), and the two paired tests of one pipeline
// against another on the same seeds: the sign test and the Wilcoxon signed-rank test.

#include <cstdint>
#include <string_view>
#include <vector>

namespace corridorsim::study {

/// Resamples of every bootstrap interval, and its level.
inline constexpr int kBootstrapResamples = 4000;
inline constexpr double kConfidenceLevel = 0.95;

/// The q-quantile (q in [0, 1]) of `values` by linear interpolation between order statistics
/// (Hyndman and Fan's type 7, numpy's and R's default). `values` must not be empty.
double Quantile(std::vector<double> values, double q);

struct Interval {
  double low = 0.0;
  double high = 0.0;
};

/// The 95 % percentile-bootstrap interval of the mean of `values` (not empty): resamples drawn
/// from RandomStream(0, 0, "study.bootstrap." + stream). One value gives [v, v].
Interval BootstrapMeanInterval(const std::vector<double>& values, std::string_view stream);

/// Paired bootstrap over the same resampled seeds of a and b (equal sizes, not empty): the
/// intervals of mean(a) - mean(b) and of mean(a) / mean(b) (the ratio's is empty, low = high =
/// NaN, when a resample's mean(b) is 0).
struct PairedIntervals {
  Interval diff;
  Interval ratio;
};
PairedIntervals BootstrapPairedIntervals(const std::vector<double>& a, const std::vector<double>& b,
                                         std::string_view stream);

/// Two-sided exact sign test of the differences' median being 0 (zeros dropped): 1 when no
/// difference is non-zero.
double SignTestP(const std::vector<double>& differences);

/// Two-sided Wilcoxon signed-rank test of the differences being symmetric about 0 (zeros dropped,
/// ties given their average rank): exact distribution of W+ for up to 50 differences without
/// ties, else the normal approximation with the tie correction and a continuity correction. 1
/// when no difference is non-zero.
double WilcoxonSignedRankP(const std::vector<double>& differences);

}  // namespace corridorsim::study
