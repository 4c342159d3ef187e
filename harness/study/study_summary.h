#pragma once
// A study's aggregate (docs/studies.md, "The summary"): from the run folders alone, so that the
// same runs give the same bytes whatever the number of workers, and whether they ran in one
// study or in shards merged later.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/study/study_file.h"

namespace corridorsim {

/// What became of one planned run.
struct StudyRunRecord {
  enum class Outcome { kFinished, kFailed, kTimedOut, kNotRun };
  std::size_t point = 0;  // index into StudySpec::points
  std::uint64_t seed = 0;
  Outcome outcome = Outcome::kNotRun;
  std::filesystem::path folder;  // the run folder (metrics.json, <pipeline>_errors.csv)
  std::string detail;            // why it failed ("exited 1", "timed out after 3600 s")
};
std::string OutcomeName(StudyRunRecord::Outcome outcome);  // finished, failed, timed_out, not_run

struct StudyExpectationResult {
  std::string point;  // the sweep point's id
  const StudyExpectation* expectation = nullptr;
  std::optional<double> measured;  // empty: not measurable (no runs, a null statistic): fails
  bool passed = false;
};

/// A run in which a pipeline diverged (docs/studies.md, "Failures").
struct StudyDivergence {
  std::string point;  // the sweep point's id
  std::string pipeline;
  std::uint64_t seed = 0;
  std::string why;  // "average NEES 243 > divergence_nees 100", "non-positive covariance (3)"...
};

struct StudySummary {
  nlohmann::ordered_json json;  // summary.json
  std::string csv;              // summary.csv: one row per point, pipeline and metric
  std::string paired_csv;       // paired.csv: one row per point, pair and metric
  std::vector<StudyExpectationResult> results;
  int failed_runs = 0;  // failed or timed out, over every point
  // Divergences of pipelines not in StudySpec::may_diverge (they fail the study), and of those
  // in it (reported only), over every point, in point, pipeline and seed order.
  std::vector<StudyDivergence> divergences, allowed_divergences;
  int not_run = 0;
  bool all_passed() const;
};

/// Reads every finished run's metrics.json and <pipeline>_errors.csv and aggregates them.
/// Throws std::runtime_error when a finished run's files cannot be read (a damaged folder).
StudySummary SummarizeStudy(const StudySpec& spec, const std::vector<StudyRunRecord>& runs);

}  // namespace corridorsim
