#pragma once
// No job's output may be, contain or lie inside one of its inputs: `evaluate RUN --out RUN
// --force` would otherwise replace the run folder it reads with its own three files, and a
// `--junit` file named like the suite would overwrite it. Every job lists what it reads (the
// scenario file and its include chain, plugin libraries, run folders, estimate, map and
// detections files, study folders) and each output it writes is checked against them before
// anything is written.

#include <filesystem>
#include <string>
#include <vector>

#include "harness/scenario/scenario.h"

namespace corridorsim {

/// Something a job reads: a file or a folder, and what it is for the message ("the scenario
/// file", "--estimate mine", "RUN_DIR").
struct JobInput {
  std::filesystem::path path;
  std::string what;
};

/// Each file of `files` as a JobInput saying `what` (a scenario's include chain, its plugins).
std::vector<JobInput> JobInputsOf(const std::vector<std::filesystem::path>& files,
                                  const std::string& what);

/// A scenario's inputs: every file of its include chain and every plugin library it loads.
std::vector<JobInput> ScenarioInputs(const Scenario& scenario);

/// `inner` is `outer` or lies inside it, both resolved as RefuseOutputOverInputs resolves them.
bool PathWithin(const std::filesystem::path& inner, const std::filesystem::path& outer);

/// Throws InputError at `command line: <option>` when `output` (a folder or a file a job writes)
/// is one of `inputs`, contains one, or lies inside one (an input folder). Both sides are
/// compared as std::filesystem::weakly_canonical gives them: absolute, `.` and `..` resolved,
/// every link of the part that exists followed, so a link or a relative spelling of an input is
/// the input. The message names the flag, the output and the input.
void RefuseOutputOverInputs(const std::filesystem::path& output, const std::string& option,
                            const std::vector<JobInput>& inputs);

}  // namespace corridorsim
