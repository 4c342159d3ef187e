// The study folder, which makes a study resumable (docs/studies.md): where a run's folder, status
// and log lie; preparing the folder (new, the same study resumed, or an earlier output replaced
// with --force); and every planned run's outcome as the folder records it.

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "harness/study/study_internal.h"
#include "harness/study/study_summary.h"

namespace corridorsim::study_internal {

namespace {
std::string SeedName(std::uint64_t seed) { return "seed_" + std::to_string(seed); }
constexpr const char* kMarker = StagedDirectory::kOutputFolderMarker;
}  // namespace

fs::path RunFolder(const fs::path& dir, const std::string& point, std::uint64_t seed) {
  return dir / "runs" / point / SeedName(seed);
}
fs::path StatusFile(const fs::path& dir, const std::string& point, std::uint64_t seed) {
  return dir / "status" / point / (SeedName(seed) + ".json");
}
fs::path LogFile(const fs::path& dir, const std::string& point, std::uint64_t seed) {
  return dir / "logs" / point / (SeedName(seed) + ".log");
}

// Prepares the study folder: new (created with its marker), the same study (resumed), or with
// --force an earlier corridorsim output (removed first). Anything else is bad input.
void PrepareFolder(const fs::path& dir, const std::string& plan_text, bool force,
                   const std::string& option) {
  const SourceLocation command_line{"command line", 0, 0};
  std::error_code error;
  if (fs::exists(dir, error) && !fs::is_directory(dir, error)) {
    throw InputError(command_line, option, "'" + dir.string() + "' is not a folder");
  }
  const bool empty = !fs::exists(dir, error) || fs::is_empty(dir, error);
  if (!empty) {
    const fs::path plan_file = dir / "study.json";
    const bool same = fs::is_regular_file(plan_file, error) &&
                      ReadRegularFile(plan_file, kMaxPlanBytes) == plan_text;
    if (same && !force) return;  // resumed
    if (!force) {
      throw InputError(command_line, option,
                       "'" + dir.string() +
                           (fs::exists(plan_file, error)
                                ? "' holds another study (its study.json differs: another "
                                  "scenario, sweep, seeds, expectations, may_diverge, build, "
                                  "plugin library or external program)"
                                : "' is not empty and holds no study") +
                           ": pass --force to start it over, or choose another folder");
    }
    if (!fs::exists(dir / kMarker, error)) {
      throw InputError(command_line, option,
                       "'" + dir.string() + "' was not written by corridorsim (no " + kMarker +
                           "): --force replaces only corridorsim's own folders");
    }
    fs::remove_all(dir, error);
    if (error) {
      throw InputError(command_line, option,
                       "cannot remove '" + dir.string() + "': " + error.message());
    }
  }
  fs::create_directories(dir, error);
  if (error) {
    throw InputError(command_line, option,
                     "cannot create '" + dir.string() + "': " + error.message());
  }
  EnsureWritableDirectory(dir);
  WriteFileAtomic(dir / kMarker, "");
  WriteFileAtomic(dir / "study.json", plan_text);
}

// Every planned run's outcome as the folder records it: finished when its run folder has
// metrics.json (run folders are committed whole), failed or timed out when its status says so.
std::vector<StudyRunRecord> CollectRecords(const StudySpec& spec, const fs::path& dir) {
  std::vector<StudyRunRecord> records;
  for (std::size_t p = 0; p < spec.points.size(); ++p) {
    for (int i = 0; i < spec.runs; ++i) {
      StudyRunRecord r;
      r.point = p;
      r.seed = spec.first_seed + static_cast<std::uint64_t>(i);
      r.folder = RunFolder(dir, spec.points[p].id, r.seed);
      std::error_code error;
      if (fs::is_regular_file(r.folder / "metrics.json", error)) {
        r.outcome = StudyRunRecord::Outcome::kFinished;
      } else if (const fs::path status = StatusFile(dir, spec.points[p].id, r.seed);
                 fs::is_regular_file(status, error)) {
        try {
          const json s = json::parse(ReadRegularFile(status, kMaxPlanBytes));
          const std::string outcome = s.at("outcome").get<std::string>();
          r.outcome = outcome == "timed_out" ? StudyRunRecord::Outcome::kTimedOut
                                             : StudyRunRecord::Outcome::kFailed;
          r.detail = s.value("detail", "");
        } catch (const std::exception&) {
          r.outcome = StudyRunRecord::Outcome::kFailed;
          r.detail = "an unreadable status file";
        }
      }
      records.push_back(std::move(r));
    }
  }
  return records;
}

}  // namespace corridorsim::study_internal
