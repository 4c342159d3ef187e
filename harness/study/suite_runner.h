#pragma once
// The child processes of `corridorsim test`: one per file (`corridorsim run` or `study`), `jobs`
// at a time, each writing its own folder and log, so that what the suite reports is the same for
// any number of jobs (docs/ci.md).

#include <filesystem>
#include <string>
#include <vector>

#include "common/io/child_process.h"

namespace corridorsim {

/// One file's job: its command and its log file.
struct SuiteCommand {
  std::vector<std::string> argv;
  std::filesystem::path log;
  std::string label;  // "run FILE" or "study FILE", for the progress lines
};

/// How one command ended, and its wall time in seconds.
struct SuiteCommandResult {
  ChildStatus status;
  double seconds = 0.0;
};

/// Runs `commands`, at most `jobs` (>= 1) at once, started in order; returns their results in
/// the order of `commands`. Prints a line as each starts. A stop signal (CatchStopSignals) is
/// forwarded to every command running; once they have ended, this process ends as the signal
/// ends a process (no report is written).
std::vector<SuiteCommandResult> RunSuiteCommands(const std::vector<SuiteCommand>& commands,
                                                 int jobs);

}  // namespace corridorsim
