// libFuzzer target: a scenario file through everything `corridorsim run --check` does before it
// generates the world (docs/fuzzing.md). LoadScenario reads the file and its include chain
// (bounds, every section's Check(), the pipelines' options, the expectations), CalibrationOf
// and the PipelineRunner build the pipelines from it, and the resolved scenario must be a fixed
// point of echoing and loading (docs/architecture.md, "Options: declared once").
//
// Bad input must end in an InputError. Anything else escaping (another exception type, an echo
// that does not load again or loads to something else) is a bug: the target aborts, and
// libFuzzer saves the input. World generation is left out: it takes tens of milliseconds per
// input (the generator has tests and the shipped scenarios of its own).
//
// The input is written to a file in a private temporary folder that holds copies of the shipped
// scenarios and tests/data/includes/*.yaml, so `include: default.yaml` works, and the files a
// loader must refuse without reading or blocking: fifo.yaml (a FIFO), zero.yaml (a link to
// /dev/zero), link_loop.yaml (a link loop), dangling.yaml, folder.yaml (a folder). An input whose
// `include:` is absolute or climbs out with `..` is skipped (returns -1), so that no include
// reaches outside that folder.

#include <cstddef>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>

#include "common/error.h"
#include "common/io/options_yaml.h"
#include "fuzz/fuzz_support.h"
#include "harness/run/pipeline_runner.h"
#include "harness/scenario/calibration.h"
#include "harness/scenario/scenario.h"

namespace {

namespace fs = std::filesystem;
using corridorsim::fuzz::Bug;
using corridorsim::fuzz::CheckShortQuotes;
using corridorsim::fuzz::WriteFile;

std::string Echo(const corridorsim::Scenario& scenario) {
  return corridorsim::OptionsYaml(corridorsim::ScenarioOptionsTable(), scenario);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::optional<corridorsim::fuzz::ScenarioInput> input =
      corridorsim::fuzz::TakeScenarioInput(data, size);
  if (!input) return -1;
  corridorsim::Scenario scenario;
  if (!corridorsim::fuzz::LoadedOrRefused(input->text, "LoadScenario", [&] {
        scenario = corridorsim::LoadScenario(input->path.string());
      })) {
    return 0;
  }
  // Building the pipelines is part of the check too (`run --check` does it): a pipeline that
  // reads a camera the scenario disabled, say, is bad input reported there, at its line.
  try {
    corridorsim::PipelineRunner pipelines(scenario, corridorsim::CalibrationOf(scenario),
                                          scenario.seed);
  } catch (const corridorsim::InputError& e) {
    CheckShortQuotes(e, input->text);
    return 0;
  } catch (const std::exception& e) {
    Bug(std::string("a loaded scenario's pipelines failed to build: ") + e.what());
  }
  // The echo is a fixed point: it loads, and loading it echoes the same text.
  const std::string echo = Echo(scenario);
  const fs::path echo_path = corridorsim::fuzz::IncludeFolder() / "echo.yaml";
  WriteFile(echo_path, echo);
  std::string again;
  try {
    again = Echo(corridorsim::LoadScenario(echo_path.string()));
  } catch (const std::exception& e) {
    Bug(std::string("the resolved scenario does not load again: ") + e.what() + "\n" + echo);
  }
  if (again != echo)
    Bug("the resolved scenario changes when loaded again:\n" + echo + "\n---\n" + again);
  return 0;
}
