#pragma once
// The one way every subcommand of `corridorsim` (harness/cli/cli.h) declares and checks its
// options: failing with `command line: <flag>: <message>`, an option (OptionalArgument: one that
// may be left out), a switch, `--set`, the options of the jobs that read a scenario (JobOptions),
// output folders (--out, --force) and the footer that ends with the subcommand's exit codes.
// Internal to the library corridorsim_cli.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "harness/scenario/job.h"

namespace corridorsim::cli {

/// Throws InputError at `command line: <flag>: <message>` (exit 2).
[[noreturn]] void Fail(const std::string& flag, const std::string& message);

/// The text as it was given, quoted and cut for a message (the input may be long or binary).
std::string Quoted(const std::string& text);
/// `(got '<text>')`, the end of most messages.
std::string Got(const std::string& text);

/// A count of a flag: a whole number in [1, max].
int WholeArgument(const std::string& text, int max, const std::string& flag);

/// The text, which names a file (or a folder): fails with "an empty file name" ("an empty folder
/// name") when it is empty.
const std::string& FileName(const std::string& text, const std::string& flag);
const std::string& FolderName(const std::string& text, const std::string& flag);

/// An option (or positional argument, a name without dashes) filling `value`, shown in --help as
/// `type_name` (CLI11's TEXT when empty).
template <typename T>
CLI::Option* AddOption(CLI::App* job, const std::string& name, T& value, const std::string& help,
                       const std::string& type_name = "") {
  CLI::Option* option = job->add_option(name, value, help);
  return type_name.empty() ? option : option->type_name(type_name);
}

/// An option that may be left out: its text, and whether it was given.
struct OptionalArgument {
  std::string text;
  CLI::Option* option = nullptr;  // set when it is added
  bool given() const { return option->count() > 0; }
};

/// An option (or positional argument) that may be left out, filling `value`.
CLI::Option* AddOption(CLI::App* job, const std::string& name, OptionalArgument& value,
                       const std::string& help, const std::string& type_name = "");

/// A switch: a flag without a value (`--flag=false` is refused).
CLI::Option* AddSwitch(CLI::App* job, const std::string& name, bool& value,
                       const std::string& help);

/// `--out`, the job's output folder: a default (`folder` non-empty: shown in --help) or none (an
/// optional folder, shown as `type_name`).
CLI::Option* AddOutFolder(CLI::App* job, std::string& folder, const std::string& help,
                          const std::string& type_name = "");
/// `--out` without a default: an output folder that may be left out.
CLI::Option* AddOutFolder(CLI::App* job, OptionalArgument& folder, const std::string& help,
                          const std::string& type_name);

/// `--set KEY=VALUE`, one per option (repeatable): harness/scenario/overrides.h.
void AddSetOption(CLI::App* job, std::vector<std::string>* settings);

/// The options of every job that reads a scenario: the scenario file, --seed, --out (its default
/// shown in --help), --force and --set. Declared on construction; CLI11 fills the members.
struct JobOptions {
  OptionalArgument scenario;
  OptionalArgument seed;
  std::string out;
  bool force = false;
  std::vector<std::string> settings;

  JobOptions(CLI::App* job, std::string default_out, const std::string& scenario_help,
             const std::string& seed_help, const std::string& out_help);
  JobOptions(const JobOptions&) = delete;  // CLI11 holds the members' addresses
  JobOptions& operator=(const JobOptions&) = delete;

  /// Checks the strings and moves them into the request.
  void Resolve(JobRequest* request) const;
};

/// The scenario argument's note on the default scenario.
inline constexpr const char* kDefaultScenarioHelp =
    "(default: ./scenarios/default.yaml if it exists, else the shipped one; the file used is "
    "printed)";

/// What a subcommand's footer says about its output folder.
enum class FolderFooter {
  kNone,    // nothing (no folder, or the footer's text says it)
  kStaged,  // written whole through a staging folder (harness/run/run_folder.h), --force
};

/// A subcommand's footer: `text` (what it writes or prints), the output folder's rules, then
/// `Exit codes: <exit_codes>` (kExitSuccess and the others, cli.h).
void SetFooter(CLI::App* job, const std::string& text, FolderFooter folder,
               const std::string& exit_codes);

}  // namespace corridorsim::cli
