#include "harness/cli/options.h"

#include <cmath>
#include <limits>
#include <utility>

#include "common/error.h"
#include "harness/cli/cli.h"
#include "harness/scenario/overrides.h"

namespace corridorsim::cli {
namespace {

const SourceLocation kCommandLine{"command line", 0, 0};

constexpr const char* kFolderFooter =
    "Output folder: written whole. Files go to a staging folder beside it (.<name>.partial-<pid>) "
    "that replaces the folder when the job is done; a failed or killed job leaves the previous "
    "folder as it was. A folder that holds files is refused (exit 2) unless --force.\n";

}  // namespace

[[noreturn]] void Fail(const std::string& flag, const std::string& message) {
  throw InputError(kCommandLine, flag, message);
}

std::string Quoted(const std::string& text) {
  std::string shown;
  for (char c : text.substr(0, 80)) {
    const auto u = static_cast<unsigned char>(c);
    shown += (u < 0x20 || u == 0x7f) ? '?' : c;
  }
  return "'" + shown + (text.size() > 80 ? "...'" : "'");
}

std::string Got(const std::string& text) { return "(got " + Quoted(text) + ")"; }

int WholeArgument(const std::string& text, int max, const std::string& flag) {
  // Parsed up to any int, so that the bound named is the count's, not the parser's.
  const double v = ParseNumberArgument(text, std::numeric_limits<int>::max(), flag);
  if (v != std::floor(v) || v < 1 || v > max)
    Fail(flag, "must be a whole number in [1, " + std::to_string(max) + "] " + Got(text));
  return static_cast<int>(v);
}

const std::string& FileName(const std::string& text, const std::string& flag) {
  if (text.empty()) Fail(flag, "an empty file name");
  return text;
}

const std::string& FolderName(const std::string& text, const std::string& flag) {
  if (text.empty()) Fail(flag, "an empty folder name");
  return text;
}

CLI::Option* AddOption(CLI::App* job, const std::string& name, OptionalArgument& value,
                       const std::string& help, const std::string& type_name) {
  value.option = AddOption(job, name, value.text, help, type_name);
  return value.option;
}

CLI::Option* AddSwitch(CLI::App* job, const std::string& name, bool& value,
                       const std::string& help) {
  return job->add_flag(name, value, help)->disable_flag_override();
}

CLI::Option* AddOutFolder(CLI::App* job, std::string& folder, const std::string& help,
                          const std::string& type_name) {
  CLI::Option* option = AddOption(job, "--out", folder, help, type_name);
  return folder.empty() ? option : option->capture_default_str();
}

CLI::Option* AddOutFolder(CLI::App* job, OptionalArgument& folder, const std::string& help,
                          const std::string& type_name) {
  folder.option = AddOutFolder(job, folder.text, help, type_name);
  return folder.option;
}

void AddSetOption(CLI::App* job, std::vector<std::string>* settings) {
  job->add_option("--set", *settings,
                  "Set a scenario (or study.*) key after the file's include chain: dotted key, "
                  "YAML value (duration_s=20, world.doors.count=4, expectations=[], "
                  "path.commands.1.0=2.5); checked like the file's keys and echoed in "
                  "scenario.yaml; repeatable, a later one wins (docs/scenarios.md)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);  // one KEY=VALUE per --set: never the scenario file after it
}

JobOptions::JobOptions(CLI::App* job, std::string default_out, const std::string& scenario_help,
                       const std::string& seed_help, const std::string& out_help)
    : out(std::move(default_out)) {
  AddOption(job, "scenario", scenario, scenario_help);
  AddOption(job, "--seed", seed, seed_help, "UINT64");
  AddOutFolder(job, out, out_help);
  AddSwitch(job, "--force", force,
            "Replace a non-empty output folder (it is replaced whole, never mixed)");
  AddSetOption(job, &settings);
}

void JobOptions::Resolve(JobRequest* request) const {
  if (scenario.given() && scenario.text.empty()) Fail("scenario", "an empty file name");
  if (seed.given()) request->seed = ParseSeedArgument(seed.text, "--seed");
  if (out.empty()) Fail("--out", "an empty folder name");
  ParseSettings(settings);  // the syntax now; the keys when the scenario is loaded
  request->settings = settings;
  request->scenario_file = scenario.text;
  request->out_dir = out;
  request->force = force;
}

void SetFooter(CLI::App* job, const std::string& text, FolderFooter folder,
               const std::string& exit_codes) {
  job->footer(text + (folder == FolderFooter::kStaged ? kFolderFooter : "") +
              "Exit codes: " + exit_codes);
}

}  // namespace corridorsim::cli
