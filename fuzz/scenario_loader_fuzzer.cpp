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

#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "common/error.h"
#include "common/io/options_yaml.h"
#include "common/io/yaml_reader.h"
#include "harness/calibration.h"
#include "harness/pipeline_runner.h"
#include "harness/scenario.h"

namespace {

namespace fs = std::filesystem;

fs::path g_dir;  // the private folder: copies of the includable files, the input, the echo

void RemoveFolder() {
  std::error_code ignored;
  fs::remove_all(g_dir, ignored);
}

[[noreturn]] void Bug(const std::string& what) {
  std::fprintf(stderr, "scenario_loader_fuzzer: BUG: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

void WriteFile(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) Bug("cannot write " + path.string());
}

// True when the input's `include:` (if it parses and has one) stays inside g_dir. The included
// copies include only each other by plain names.
bool IncludeStaysInside(const std::string& text) {
  try {
    const corridorsim::YamlDocument doc = corridorsim::YamlDocument::FromString(text, "input.yaml");
    const YAML::Node include = doc.root["include"];
    if (!include || !include.IsScalar()) return true;
    const fs::path target(include.Scalar());
    if (target.is_absolute() || target.has_root_name() || target.has_root_directory()) {
      return false;
    }
    for (const fs::path& part : target) {
      if (part == "..") return false;
    }
  } catch (const corridorsim::InputError&) {
    // The loader stops at the same error before it follows any include.
  }
  return true;
}

// A message quotes at most a short excerpt of the input (InputExcerpt: a path at most 240 bytes,
// a key 120, a value 80): any 300 bytes of it in a row contain one of these aligned 250-byte
// windows (a step of 50), and no quote of 240 bytes or less does.
void CheckShortQuotes(const corridorsim::InputError& error, const std::string& text) {
  const std::string message = error.what();
  for (std::size_t at = 0; at + 250 <= text.size(); at += 50) {
    if (message.find(text.substr(at, 250)) != std::string::npos) {
      Bug("an error message quotes the input at length: " + message);
    }
  }
}

std::string Echo(const corridorsim::Scenario& scenario) {
  return corridorsim::OptionsYaml(corridorsim::ScenarioOptionsTable(), scenario);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  char pattern[] = "/tmp/corridorsim_fuzz_XXXXXX";
  const char* dir = ::mkdtemp(pattern);
  if (!dir) Bug("mkdtemp failed");
  g_dir = dir;
  std::atexit(&RemoveFolder);
  const fs::path source(CORRIDORSIM_SOURCE_DIR);
  for (const fs::path& folder : {source / "scenarios", source / "tests/data/includes"}) {
    for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
      if (entry.path().extension() == ".yaml") {
        fs::copy_file(entry.path(), g_dir / entry.path().filename(),
                      fs::copy_options::overwrite_existing);
      }
    }
  }
  if (::mkfifo((g_dir / "fifo.yaml").c_str(), 0600) != 0) Bug("mkfifo failed");
  fs::create_symlink("/dev/zero", g_dir / "zero.yaml");
  fs::create_symlink(g_dir / "link_loop2.yaml", g_dir / "link_loop.yaml");
  fs::create_symlink(g_dir / "link_loop.yaml", g_dir / "link_loop2.yaml");
  fs::create_symlink(g_dir / "nowhere.yaml", g_dir / "dangling.yaml");
  fs::create_directory(g_dir / "folder.yaml");
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  if (!IncludeStaysInside(text)) return -1;
  const fs::path input = g_dir / "input.yaml";
  WriteFile(input, text);
  corridorsim::Scenario scenario;
  try {
    scenario = corridorsim::LoadScenario(input.string());
  } catch (const corridorsim::InputError& e) {
    CheckShortQuotes(e, text);
    return 0;  // bad input, reported as it should be
  } catch (const std::exception& e) {
    Bug(std::string("LoadScenario threw something other than InputError: ") + e.what());
  }
  // Building the pipelines is part of the check too (`run --check` does it): a pipeline that
  // reads a camera the scenario disabled, say, is bad input reported there, at its line.
  try {
    corridorsim::PipelineRunner pipelines(scenario, corridorsim::CalibrationOf(scenario),
                                          scenario.seed);
  } catch (const corridorsim::InputError& e) {
    CheckShortQuotes(e, text);
    return 0;
  } catch (const std::exception& e) {
    Bug(std::string("a loaded scenario's pipelines failed to build: ") + e.what());
  }
  // The echo is a fixed point: it loads, and loading it echoes the same text.
  const std::string echo = Echo(scenario);
  const fs::path echo_path = g_dir / "echo.yaml";
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
