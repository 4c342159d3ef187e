#pragma once
// The subcommands of `corridorsim`, one family per file; ParseCommandLine (cli.cpp) adds them in
// the order of `corridorsim --help` and resolves the one given. Internal to corridorsim_cli.

#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "harness/cli/cli.h"

namespace corridorsim::cli {

/// One subcommand: its options are declared (harness/cli/options.h) when it is added, into
/// members that CLI11 fills while parsing; Resolve checks them into the CommandLine (its `job`
/// and request) when this subcommand was given.
class Subcommand {
 public:
  // Adds subcommand `name` to `app`; `description` is its line in `corridorsim --help`.
  Subcommand(CLI::App* app, const std::string& name, const std::string& description)
      : job_(app->add_subcommand(name, description)) {}
  virtual ~Subcommand() = default;
  Subcommand(const Subcommand&) = delete;  // CLI11 holds the members' addresses
  Subcommand& operator=(const Subcommand&) = delete;

  bool given() const { return job_->parsed(); }  // this subcommand was parsed
  virtual void Resolve(CommandLine* parsed) const = 0;

 protected:
  CLI::App* const job_;
};

// Each adds its subcommand to `app`; `parsed` is where switches that are request fields go.
// world_commands.cpp: the world and the robot in it.
std::unique_ptr<Subcommand> AddWorldCommand(CLI::App* app);
std::unique_ptr<Subcommand> AddSnapshotCommand(CLI::App* app);
std::unique_ptr<Subcommand> AddDriveCommand(CLI::App* app, CommandLine* parsed);
std::unique_ptr<Subcommand> AddWhereCommand(CLI::App* app);
// run_command.cpp
std::unique_ptr<Subcommand> AddRunCommand(CLI::App* app, CommandLine* parsed);
std::unique_ptr<Subcommand> AddReplayCommand(CLI::App* app, CommandLine* parsed);
// workbench_commands.cpp: developing detectors.
std::unique_ptr<Subcommand> AddDetectCommand(CLI::App* app);
std::unique_ptr<Subcommand> AddTrainDetectorsCommand(CLI::App* app);
std::unique_ptr<Subcommand> AddDatasetCommand(CLI::App* app);
std::unique_ptr<Subcommand> AddScoreCommand(CLI::App* app);
// study_commands.cpp: many runs.
std::unique_ptr<Subcommand> AddStudyCommand(CLI::App* app);  // with `study merge`
std::unique_ptr<Subcommand> AddTestCommand(CLI::App* app);
// evaluate_plugin_commands.cpp: other systems' results and code.
std::unique_ptr<Subcommand> AddEvaluateCommand(CLI::App* app);
std::unique_ptr<Subcommand> AddPluginCommand(CLI::App* app);

}  // namespace corridorsim::cli
