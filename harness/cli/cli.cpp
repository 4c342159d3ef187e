// ParseCommandLine: the `corridorsim` application, its subcommands (one family per file,
// subcommands.h), help and version, and the one subcommand given resolved into its request.
#include "harness/cli/cli.h"

#include <algorithm>
#include <iterator>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "harness/cli/options.h"
#include "harness/cli/subcommands.h"

namespace corridorsim {
namespace {

// The subcommands, in the order of `corridorsim --help`.
constexpr const char* kJobs[] = {"world",  "snapshot",        "run",     "replay", "drive", "where",
                                 "detect", "train-detectors", "dataset", "score",  "study", "test",
                                 "plugin", "evaluate"};

// "world, snapshot, ..., plugin or evaluate (see corridorsim --help)" for the messages.
std::string JobList() {
  std::string list;
  for (std::size_t i = 0; i < std::size(kJobs); ++i) {
    list += std::string(i == 0 ? "" : i + 1 < std::size(kJobs) ? ", " : " or ") + kJobs[i];
  }
  return list + " (see corridorsim --help)";
}

}  // namespace

CommandLine ParseCommandLine(const std::vector<std::string>& args) {
  using cli::Fail;
  CLI::App app{"corridorsim: a simulation harness for corridor SLAM", "corridorsim"};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Show the help of every subcommand");
  app.set_version_flag("--version", std::string("corridorsim"),
                       "Print the version, the git describe of the build and the SDK ABI version");
  app.footer(
      "Exit codes: 0 success, 2 bad input, 1 other failures; `run` also 3 (an expectation "
      "failed), 4 (results written, an extra failed) and 5 (a pipeline failed; the others' "
      "results are written); `score` also 3 (an --expect failed); "
      "`evaluate` also 3 (an --expect failed) and 4 (results written, plots/ failed). Run "
      "`corridorsim <subcommand> --help`.");

  CommandLine parsed;
  // Switches that are fields of a request (run --keep-frames, --check; drive --save-frames) are
  // filled in `parsed` directly.
  std::unique_ptr<cli::Subcommand> jobs[] = {
      cli::AddWorldCommand(&app),          cli::AddSnapshotCommand(&app),
      cli::AddRunCommand(&app, &parsed),   cli::AddReplayCommand(&app, &parsed),
      cli::AddDriveCommand(&app, &parsed), cli::AddWhereCommand(&app),
      cli::AddDetectCommand(&app),         cli::AddTrainDetectorsCommand(&app),
      cli::AddDatasetCommand(&app),        cli::AddScoreCommand(&app),
      cli::AddStudyCommand(&app),          cli::AddTestCommand(&app),
      cli::AddEvaluateCommand(&app),       cli::AddPluginCommand(&app)};

  if (!args.empty() && !args[0].empty() && args[0][0] != '-' &&
      std::find(std::begin(kJobs), std::end(kJobs), args[0]) == std::end(kJobs)) {
    Fail("", "unknown subcommand " + cli::Quoted(args[0]) + ": expected " + JobList());
  }
  // CLI11 takes the arguments last first.
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
  } catch (const CLI::CallForHelp&) {
    parsed.job = CommandLine::Job::kHelp;
    parsed.help_text = app.help();
    return parsed;
  } catch (const CLI::CallForVersion&) {
    parsed.job = CommandLine::Job::kVersion;
    return parsed;
  } catch (const CLI::CallForAllHelp&) {
    parsed.job = CommandLine::Job::kHelp;
    parsed.help_text = app.help("", CLI::AppFormatMode::All);
    return parsed;
  } catch (const CLI::ParseError& e) {
    Fail("", std::string(e.what()) + " (see corridorsim --help)");
  }

  for (const std::unique_ptr<cli::Subcommand>& job : jobs) {
    if (job->given()) {
      job->Resolve(&parsed);
      return parsed;
    }
  }
  Fail("", "a subcommand is required: " + JobList());
}

}  // namespace corridorsim
