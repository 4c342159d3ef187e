#include "harness/metrics/consistency.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <set>

#include <Eigen/Cholesky>

#include "common/io/stable_json.h"
#include "harness/metrics/stats.h"

namespace corridorsim {
namespace metrics {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using slam::LandmarkType;

std::optional<double> Nees(const Vector3d& error, const Matrix3d& covariance) {
  if (!covariance.allFinite()) return std::nullopt;
  // A sample whose sigma in x, y or yaw is below kNeesMinSigma has no meaningful NEES: the start
  // pose is known exactly, and in the first steps after it the filter's covariance is below the
  // simulation's own micrometre transients (wheel contacts settling), which no filter models;
  // one such sample reads 1e17 and would be the whole mean.
  if ((covariance.diagonal().array() < kNeesMinSigma * kNeesMinSigma).any()) return std::nullopt;
  const Eigen::LLT<Matrix3d> llt(covariance);
  if (llt.info() != Eigen::Success) return std::nullopt;
  // LLT accepts some matrices with a zero pivot; require a strictly positive diagonal of L.
  const Matrix3d l = llt.matrixL();
  if ((l.diagonal().array() <= 0.0).any()) return std::nullopt;
  return error.dot(llt.solve(error));
}

void AddNeesMetrics(const MatchedTrajectory& matched, const MetricWriter& out) {
  const std::vector<MatchedSample>& samples = matched.samples;
  if (samples.empty()) return;
  // Samples whose covariance is not positive definite (the shared start pose has a zero
  // covariance) are skipped and counted.
  const double sample_low = ChiSquareQuantile(3, kBandLowerTail);
  const double sample_high = ChiSquareQuantile(3, kBandUpperTail);
  std::size_t used = 0;
  std::size_t in_band = 0;
  double sum = 0.0;
  double last = 0.0;
  for (const MatchedSample& s : samples) {
    const std::optional<double> nees = Nees(PoseError(s.estimate, s.truth), s.covariance);
    if (!nees) continue;
    ++used;
    sum += *nees;
    last = *nees;
    if (*nees >= sample_low && *nees <= sample_high) ++in_band;
  }
  out.Count("nees_samples", used);
  out.Count("nees_skipped", samples.size() - used);
  if (used == 0) {
    out.Null("nees_mean");
    out.Null("nees_in_band_fraction");
    out.Null("nees_final");
    return;
  }
  const double n = static_cast<double>(used);
  out.Set("nees_mean", sum / n);
  out.Fraction("nees_in_band_fraction", in_band, used);
  // No chi2(3N) / N band for the mean: consecutive NEES of one run are strongly correlated (the
  // error and covariance change little between odometry messages), so N samples are far fewer
  // independent ones and such a band would be far too narrow. The last sample alone is one
  // honest chi2(3) draw; the mean's band is judged over seeds
  // (tests/harness/scenario_runs_test.py).
  out.Set("nees_final", last);
}

namespace {
// An innovation no NIS statistic can use (counted by AddNisMetrics, left out of the CSV).
bool MalformedInnovation(const slam::Innovation& innovation) {
  return innovation.dof < 1 || !std::isfinite(innovation.nis) || innovation.nis < 0.0;
}
}  // namespace

std::size_t AddNisMetrics(const std::vector<slam::Innovation>& innovations,
                          const MetricWriter& out) {
  // The shipped landmark types in schema order, then the pipeline's own measurement types by
  // name (slam::MeasurementType; their names cannot be a landmark type's).
  std::vector<std::string> names;
  for (const LandmarkType type : kAllTypes) names.push_back(slam::LandmarkTypeName(type));
  std::set<std::string> own;
  std::vector<std::string> name_of;  // each innovation's
  name_of.reserve(innovations.size());
  for (const slam::Innovation& innovation : innovations) {
    if (!innovation.measurement.empty()) own.insert(innovation.measurement);
    name_of.push_back(slam::MeasurementName(innovation));
  }
  names.insert(names.end(), own.begin(), own.end());
  std::size_t malformed = 0;
  for (const std::string& name : names) {
    std::size_t count = 0;
    std::size_t gated = 0;
    std::size_t in_band = 0;
    double sum = 0.0;
    double dof_sum = 0.0;
    for (std::size_t k = 0; k < innovations.size(); ++k) {
      const slam::Innovation& innovation = innovations[k];
      if (name_of[k] != name) continue;
      if (MalformedInnovation(innovation)) {
        ++malformed;
        continue;
      }
      if (!innovation.accepted) {
        ++gated;
        continue;
      }
      ++count;
      sum += innovation.nis;
      dof_sum += innovation.dof;
      if (innovation.nis >= ChiSquareQuantile(innovation.dof, kBandLowerTail) &&
          innovation.nis <= ChiSquareQuantile(innovation.dof, kBandUpperTail)) {
        ++in_band;
      }
    }
    if (count == 0 && gated == 0) continue;
    const MetricWriter t = out.Sub("nis").Sub(name);
    t.Count("count", count);
    t.Count("gated", gated);
    if (count == 0) {
      t.Null("mean");
      t.Null("in_band_fraction");
      t.Null("mean_band_low");
      t.Null("mean_band_high");
    } else {
      const double n = static_cast<double>(count);
      t.Set("mean", sum / n);
      t.Fraction("in_band_fraction", in_band, count);
      // The sum of independent chi2(d_i) is chi2(sum d_i).
      t.Set("mean_band_low", ChiSquareQuantile(dof_sum, kBandLowerTail) / n);
      t.Set("mean_band_high", ChiSquareQuantile(dof_sum, kBandUpperTail) / n);
    }
  }
  return malformed;
}

}  // namespace metrics

void WriteErrorSeriesCsv(const metrics::MatchedTrajectory& matched,
                         const std::function<void(std::string_view)>& sink) {
  using metrics::MatchedSample;
  sink("t,ex_m,ey_m,eyaw_rad,sigma_x_m,sigma_y_m,sigma_yaw_rad,nees\n");
  std::string csv;  // one line at a time
  // One field and its comma (or the line's end): the value with `decimals` decimals, or nothing
  // where it is not finite (a NaN or infinite variance): the readers take an empty field as
  // missing (harness/study/study_summary.cpp, scripts/plot_run.py, scripts/p1_study.py,
  // p3_study.py).
  const auto field = [&csv](double value, int decimals, char end) {
    if (std::isfinite(value)) {
      char text[64];
      std::snprintf(text, sizeof(text), "%.*f", decimals, value);
      csv += text;
    }
    csv += end;
  };
  const auto m = [](double v) { return RoundToStep(v, json_steps::kMetres); };
  const auto rad = [](double v) { return RoundToStep(v, json_steps::kRad); };
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  for (const MatchedSample& s : matched.samples) {
    const Eigen::Vector3d e = metrics::PoseError(s.estimate, s.truth);
    Eigen::Vector3d sigma;
    for (int i = 0; i < 3; ++i) {
      const double variance = s.covariance(i, i);
      sigma[i] = std::isfinite(variance) ? std::sqrt(std::max(variance, 0.0)) : kNaN;
    }
    csv.clear();
    field(ToSeconds(s.stamp_ns), 9, ',');
    field(m(e.x()), 6, ',');
    field(m(e.y()), 6, ',');
    field(rad(e.z()), 8, ',');
    field(m(sigma.x()), 6, ',');
    field(m(sigma.y()), 6, ',');
    field(rad(sigma.z()), 8, ',');
    const std::optional<double> nees = metrics::Nees(e, s.covariance);
    field(nees ? RoundToStep(*nees, json_steps::kRatio) : kNaN, 6, '\n');
    sink(csv);
  }
}

std::string ErrorSeriesCsv(const std::vector<TruthPose>& truth, const PipelineRecord& pipeline) {
  std::string csv;
  WriteErrorSeriesCsv(metrics::MatchToTruth(truth, pipeline.estimates),
                      [&csv](std::string_view line) { csv += line; });
  return csv;
}

std::string NisSeriesCsv(const PipelineRecord& pipeline) {
  if (pipeline.innovations.empty()) return "";
  std::string csv = "t,type,dof,nis,accepted\n";
  char line[1024];  // a name of at most 32 bytes; a NIS up to 1e308 has 309 digits
  for (const slam::Innovation& i : pipeline.innovations) {
    if (metrics::MalformedInnovation(i)) continue;
    std::snprintf(line, sizeof(line), "%.9f,%s,%d,%.6f,%d\n", ToSeconds(i.stamp_ns),
                  slam::MeasurementName(i).c_str(), i.dof, RoundToStep(i.nis, json_steps::kRatio),
                  i.accepted ? 1 : 0);
    csv += line;
  }
  return csv;
}

}  // namespace corridorsim
