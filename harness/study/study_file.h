#pragma once
// A study: one scenario run over many seeds, optionally at every point of a sweep over scenario
// keys, aggregated into statistics (docs/studies.md). A study file is a scenario file (its own
// keys and `include:` chain give the scenario) with a `study:` section; a plain scenario file is
// a study of its defaults. Loading checks everything, every sweep point's scenario included,
// before anything runs: a bad key is an InputError at its line.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "harness/run/job_inputs.h"
#include "harness/scenario/scenario.h"

namespace corridorsim {

// Bounds of a study (each far above the shipped studies; docs/studies.md, "Bounds").
inline constexpr int kMaxStudyRuns = 10000;         // seeds per sweep point
inline constexpr int kMaxSweepValues = 100;         // values of one `vary:` key
inline constexpr int kMaxSweepPoints = 1000;        // points of the whole sweep (the product)
inline constexpr long kMaxStudyTotalRuns = 100000;  // points x seeds
inline constexpr int kMaxStudyMetrics = 64;         // entries of `metrics:`
inline constexpr double kMaxRunTimeoutSeconds = 1e6;

/// A summary statistic an expectation can name (study expectations, below).
struct StudyExpectation {
  enum class Kind {
    kPipelineStat,  // <pipeline>.<metric>.<stat>: mean, median, p95, ci_low, ci_high, min, max
    kNees,          // <pipeline>.nees.<stat>: average, in_band_fraction
    kRuns,          // <pipeline>.runs.<stat>: finished, diverged
    kPaired,        // paired(<a>, <b>).<metric>.<stat>: diff, diff_ci_low, diff_ci_high, ratio,
                    // ratio_ci_low, ratio_ci_high, p_sign, p_wilcoxon
    kFailedRuns,    // runs.failed: runs of the point that crashed or timed out
  };
  Kind kind = Kind::kPipelineStat;
  std::string pipeline;  // a (kPipelineStat, kNees, kRuns, kPaired)
  std::string other;     // b (kPaired)
  std::string metric;    // kPipelineStat, kPaired
  std::string stat;
  enum class Op { kLess, kLessEqual, kGreater, kGreaterEqual };
  Op op = Op::kLess;
  double value = 0.0;
  std::string text;  // as written
  SourceLocation location;
};

/// One point of the sweep: the scenario with the point's values applied.
struct StudyPoint {
  std::string id;  // "p000", "p001", ... in sweep order (the last key varies fastest)
  // (key, value as flow YAML) in `vary:` order; empty without a sweep.
  std::vector<std::pair<std::string, std::string>> values;
  Scenario scenario;
};

struct StudySpec {
  std::string file;          // as given
  bool has_section = false;  // false: a plain scenario file
  int runs = 10;             // seeds per point: first_seed, first_seed + 1, ...
  std::uint64_t first_seed = 1;
  double run_timeout_s = 3600.0;
  double divergence_nees = 100.0;    // a pipeline whose average NEES is above it diverged
  double time_step_s = 1.0;          // the grid of the series over time (NEES, error)
  std::vector<std::string> metrics;  // summarised per pipeline (defaults and `metrics:`)
  std::vector<std::string> vary_keys;
  std::vector<StudyPoint> points;      // at least one
  std::vector<std::string> pipelines;  // enabled, in scenario order (the same at every point)
  std::vector<StudyExpectation> expectations;
  // Pipelines whose divergence is expected (baselines such as odometry): their diverged runs are
  // counted and reported but do not fail the study; a diverged run of any other pipeline makes
  // `study` exit 1 naming it (docs/studies.md, "Failures"). The scenario's `baseline: true`
  // pipelines, `study.may_diverge` and --may-diverge, in scenario order.
  std::vector<std::string> may_diverge;
};

/// What a study reads: every point's include chain and plugin libraries (ScenarioInputs), once.
std::vector<JobInput> StudyInputs(const StudySpec& spec);

/// The per-pipeline metrics every study summarises (before the file's `metrics:`).
const std::vector<std::string>& DefaultStudyMetrics();

/// Loads `path` as a study; `runs` and `first_seed` override the file's (the command line), and
/// `settings` (`--set KEY=VALUE`, harness/scenario/overrides.h) are applied after its include
/// chain, to the scenario of every point and to the `study:` section (a key the sweep varies
/// cannot be set). Throws InputError naming file, line and key (or `--set` and the key).
StudySpec LoadStudy(const std::string& path, std::optional<int> runs,
                    std::optional<std::uint64_t> first_seed,
                    const std::vector<std::string>& settings = {});

/// Adds `names` (study.may_diverge, or the command line's --may-diverge) to spec->may_diverge,
/// keeping scenario order. A name that is not an enabled pipeline is an InputError under key
/// `option` at its entry of `locations`, or at "command line" without one.
void AddMayDiverge(StudySpec* spec, const std::vector<std::string>& names,
                   const std::string& option, const std::vector<SourceLocation>& locations = {});

/// Parses one study expectation (see StudyExpectation); returns the error, or nothing.
std::optional<std::string> ParseStudyExpectation(const std::string& text, StudyExpectation* out);

}  // namespace corridorsim
