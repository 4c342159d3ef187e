// libFuzzer target: a study file through LoadStudy (harness/study/study_file.h), all that
// `corridorsim study` and `corridorsim test` check before anything runs (docs/fuzzing.md,
// docs/studies.md): the scenario and its include chain, the `study:` section (runs, seeds, bounds,
// metrics, may_diverge, expectations) and every point of a `vary:` sweep, each a scenario of its
// own.
//
// Bad input must end in an InputError that quotes the input only briefly. Anything else escaping
// is a bug, and so is a loaded study outside the bounds docs/studies.md states (runs, points,
// points x runs, seeds that overflow), a may_diverge name that is not a pipeline of the study,
// an expectation that does not parse again to itself, or a point whose resolved scenario does not
// load again. The command line's --runs and --seed are checked too: a study loaded again with the
// last seed and two runs per point must be refused (the seeds would overflow).
//
// The input is written to input.yaml in the private folder of fuzz/fuzz_support.h (copies of the
// shipped scenarios, so `include: default.yaml` works, and files a loader must refuse); an input
// whose `include:` is absolute or climbs out with `..` is skipped (returns -1).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "common/error.h"
#include "fuzz/fuzz_support.h"
#include "harness/scenario/scenario.h"
#include "harness/study/study_file.h"

namespace {

namespace fs = std::filesystem;
using corridorsim::InputError;
using corridorsim::StudyExpectation;
using corridorsim::StudySpec;
using corridorsim::fuzz::Bug;

// The bounds of a loaded study and the consistency of what it holds.
void CheckSpec(const StudySpec& spec) {
  if (spec.runs < 1 || spec.runs > corridorsim::kMaxStudyRuns) {
    Bug("runs out of bounds: " + std::to_string(spec.runs));
  }
  if (spec.points.empty() ||
      spec.points.size() > static_cast<std::size_t>(corridorsim::kMaxSweepPoints)) {
    Bug("points out of bounds: " + std::to_string(spec.points.size()));
  }
  if (static_cast<long>(spec.points.size()) * spec.runs > corridorsim::kMaxStudyTotalRuns) {
    Bug("points x runs out of bounds");
  }
  if (spec.first_seed >
      std::numeric_limits<std::uint64_t>::max() - static_cast<std::uint64_t>(spec.runs - 1)) {
    Bug("the seeds overflow");
  }
  if (!(spec.run_timeout_s >= 1.0 && spec.run_timeout_s <= corridorsim::kMaxRunTimeoutSeconds) ||
      !(spec.time_step_s > 0.0) || !(spec.divergence_nees >= 1.0)) {
    Bug("a bound of study: not checked");
  }
  if (spec.pipelines.empty()) Bug("a study without a pipeline");
  std::size_t at = 0;  // may_diverge: pipelines of the study, in their order
  for (const std::string& name : spec.may_diverge) {
    const auto it =
        std::find(spec.pipelines.begin() + static_cast<long>(at), spec.pipelines.end(), name);
    if (it == spec.pipelines.end())
      Bug("may_diverge names '" + name + "': not a pipeline, or out of order");
    at = static_cast<std::size_t>(it - spec.pipelines.begin()) + 1;
  }
  for (std::size_t i = 0; i < spec.points.size(); ++i) {
    if (spec.points[i].values.size() != spec.vary_keys.size()) Bug("a point without every key");
    if (i > 0 && !(spec.points[i - 1].id < spec.points[i].id)) Bug("point ids not in order");
  }
  for (const StudyExpectation& e : spec.expectations) {
    StudyExpectation again;
    if (const auto error = corridorsim::ParseStudyExpectation(e.text, &again)) {
      Bug("a loaded expectation does not parse again: " + *error);
    }
    if (again.kind != e.kind || again.pipeline != e.pipeline || again.other != e.other ||
        again.metric != e.metric || again.stat != e.stat || again.op != e.op ||
        again.value != e.value) {
      Bug("an expectation parses again to something else: " + e.text);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::optional<corridorsim::fuzz::ScenarioInput> input =
      corridorsim::fuzz::TakeScenarioInput(data, size);
  if (!input) return -1;
  StudySpec spec;
  if (!corridorsim::fuzz::LoadedOrRefused(input->text, "LoadStudy", [&] {
        spec = corridorsim::LoadStudy(input->path.string(), std::nullopt, std::nullopt);
      })) {
    return 0;
  }
  CheckSpec(spec);
  // Each point's scenario is what `corridorsim run` gets (points/<id>.yaml): it loads again.
  // The first and the last point (a sweep's extremes) stand for all.
  for (const std::size_t i : {std::size_t{0}, spec.points.size() - 1}) {
    const fs::path point = corridorsim::fuzz::IncludeFolder() / "point.yaml";
    corridorsim::fuzz::WriteFile(
        point, corridorsim::ResolvedScenarioYaml(spec.points[i].scenario, spec.first_seed));
    try {
      corridorsim::LoadScenario(point.string());
    } catch (const std::exception& e) {
      Bug("point " + spec.points[i].id + "'s scenario does not load again: " + e.what());
    }
  }
  // --seed 18446744073709551615 --runs 2: the seeds overflow, refused as bad input.
  try {
    corridorsim::LoadStudy(input->path.string(), 2, std::numeric_limits<std::uint64_t>::max());
    Bug("a study whose seeds overflow was loaded");
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    Bug(std::string("LoadStudy threw something other than InputError: ") + e.what());
  }
  return 0;
}
