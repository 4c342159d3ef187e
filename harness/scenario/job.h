#pragma once
// What every `corridorsim` job that reads a scenario is asked for (world, snapshot, drive, run,
// and the coming study).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace corridorsim {

struct JobRequest {
  std::string scenario_file;          // empty: none given (main picks the default)
  std::optional<std::uint64_t> seed;  // overrides the scenario's seed
  std::filesystem::path out_dir;      // the job's output folder
  bool force = false;                 // --force: replace a non-empty output folder (whole)
  // --set KEY=VALUE (harness/scenario/overrides.h): scenario keys applied after the file's
  // include chain, in order (a later one wins).
  std::vector<std::string> settings;
};

}  // namespace corridorsim
