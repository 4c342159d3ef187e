// `corridorsim study merge` (MergeStudies): study folders of the same plan (shards, or partial
// resumes) combined into one, refused when they are of another plan or lack runs of it; then the
// summary (study_finish.cpp), byte for byte the one the whole study gives.

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "common/io/sha256.h"
#include "harness/run/run_folder.h"
#include "harness/study/study.h"
#include "harness/study/study_file.h"
#include "harness/study/study_internal.h"

namespace corridorsim {

using namespace study_internal;

namespace {

// True when `status` records a run that failed or timed out (a status that says "finished"
// stands for a run folder, which must be there).
bool RecordedFailure(const fs::path& status) {
  std::error_code error;
  if (!fs::is_regular_file(status, error)) return false;
  try {
    return json::parse(ReadRegularFile(status, kMaxPlanBytes)).value("outcome", "") != "finished";
  } catch (const std::exception&) {
    return true;  // unreadable: recorded as a failure (CollectRecords)
  }
}

// Every run of the plan must be in one of the folders to merge (finished, or recorded as failed
// or timed out), or already in the output folder of a resumed merge: a merge that lacks runs (a
// shard not given, or one that has not ended) would summarise part of the study and judge its
// expectations on that part. Refused as incomplete input (exit 2), naming the missing runs and,
// when the folders are shards, the shards they belong to.
void RequireCompleteMerge(const StudySpec& spec, const StudyRequest& request,
                          const std::string& plan_text) {
  constexpr std::size_t kListed = 12;  // runs and shards named in the message
  std::vector<fs::path> sources = request.merge_dirs;
  std::error_code error;
  const fs::path out_plan = request.out_dir / "study.json";
  if (!request.force && fs::is_regular_file(out_plan, error) &&
      ReadRegularFile(out_plan, kMaxPlanBytes) == plan_text) {
    sources.push_back(request.out_dir);
  }
  long shards = 0;  // N of the folders' --shard K/N, when they say so alike
  for (const fs::path& d : request.merge_dirs) {
    try {
      const json shard = json::parse(ReadRegularFile(d / "shard.json", kMaxPlanBytes));
      const long of = shard.at("of").get<long>();
      shards = shards == 0 || shards == of ? of : -1;
    } catch (const std::exception&) {
      // not a shard (a whole or resumed study folder)
    }
  }
  long missing = 0, index = 0;
  std::string runs;
  std::set<long> missing_shards;
  for (const StudyPoint& point : spec.points) {
    for (int i = 0; i < spec.runs; ++i, ++index) {
      const std::uint64_t seed = spec.first_seed + static_cast<std::uint64_t>(i);
      const bool found = std::any_of(sources.begin(), sources.end(), [&](const fs::path& d) {
        return fs::is_regular_file(RunFolder(d, point.id, seed) / "metrics.json", error) ||
               RecordedFailure(StatusFile(d, point.id, seed));
      });
      if (found) continue;
      if (++missing <= static_cast<long>(kListed)) {
        runs += (runs.empty() ? "" : ", ") + point.id + " seed " + std::to_string(seed);
      }
      if (shards > 0) missing_shards.insert(index % shards + 1);
    }
  }
  if (missing == 0) return;
  std::string message = std::to_string(missing) + " of the plan's " + std::to_string(index) +
                        " run(s) are in none of the folders (" + runs +
                        (missing > static_cast<long>(kListed) ? ", ..." : "") + ")";
  if (!missing_shards.empty()) {
    std::string list;
    std::size_t listed = 0;
    for (const long k : missing_shards) {
      if (++listed > kListed) {
        list += ", ...";
        break;
      }
      list += (list.empty() ? "" : ", ") + std::to_string(k) + "/" + std::to_string(shards);
    }
    message += "; missing from shard(s) " + list;
  }
  throw InputError(SourceLocation{"command line", 0, 0}, "DIR",
                   message +
                       ": the merge is incomplete; merge every shard, each once it has ended "
                       "(a shard resumes with its own command)");
}

}  // namespace

int MergeStudies(const StudyRequest& request) {
  const SourceLocation command_line{"command line", 0, 0};
  if (request.merge_dirs.empty()) throw InputError(command_line, "DIR", "no study folder given");
  std::string plan_text;
  for (const fs::path& d : request.merge_dirs) {
    const fs::path plan_file = d / "study.json";
    std::error_code error;
    if (!fs::is_regular_file(plan_file, error)) {
      throw InputError(command_line, "DIR", "'" + d.string() + "' holds no study.json");
    }
    const std::string text = ReadRegularFile(plan_file, kMaxPlanBytes);
    if (plan_text.empty()) {
      plan_text = text;
    } else if (text != plan_text) {
      std::string why = "the plans differ";
      try {
        const std::string plugins = PluginDifference(json::parse(plan_text), json::parse(text));
        if (!plugins.empty()) why = plugins;
      } catch (const json::exception&) {
        // not JSON: "the plans differ" says enough
      }
      throw InputError(SourceLocation{plan_file.string(), 0, 0}, "",
                       "another study than " + (request.merge_dirs[0] / "study.json").string() +
                           " (" + why + ")");
    }
  }
  // The output folder is none of the folders merged and lies inside none; it holds one only as
  // the --slurm layout does, under its shards/ (never removed: --force is refused below).
  std::vector<JobInput> inputs;
  for (const fs::path& d : request.merge_dirs) {
    if (!PathWithin(d, request.out_dir / "shards")) inputs.push_back({d, "a folder to merge"});
  }
  RefuseOutputOverInputs(request.out_dir, "--out", inputs);
  const fs::path first_plan = request.merge_dirs[0] / "study.json";
  const json plan = ReadPlan(first_plan);
  const StudySpec spec = SpecFromPlan(plan, first_plan);
  // The points' scenarios, read (and checked against the plan's hashes) before anything is
  // written.
  std::vector<std::string> point_yaml;
  for (std::size_t i = 0; i < spec.points.size(); ++i) {
    const fs::path from = request.merge_dirs[0] / "points" / (spec.points[i].id + ".yaml");
    point_yaml.push_back(ReadRegularFile(from, kMaxPlanBytes));
    if (Sha256Hex(point_yaml.back()) != plan["points"][i].value("scenario_sha256", "")) {
      throw InputError(
          SourceLocation{from.string(), 0, 0}, "",
          "not the scenario of the plan (its SHA-256 differs from " + first_plan.string() + "'s)");
    }
  }
  const fs::path dir = request.out_dir;
  std::error_code error;
  const fs::path out_abs = fs::weakly_canonical(dir, error);
  if (request.force) {
    // --force removes the output folder first: never while it holds a folder to merge (the
    // layout of --slurm merges <study>/shards/K into <study>; that merge resumes, no --force).
    for (const fs::path& d : request.merge_dirs) {
      const fs::path inside = fs::weakly_canonical(d, error).lexically_relative(out_abs);
      if (!inside.empty() && *inside.begin() != "..") {
        throw InputError(command_line, "--force",
                         "'" + InputExcerpt(dir.string()) + "' holds '" + InputExcerpt(d.string()) +
                             "', a folder to merge, which --force would remove before it is read");
      }
    }
  }
  RequireCompleteMerge(spec, request, plan_text);
  PrepareFolder(dir, plan_text, request.force, "--out");
  fs::create_directories(dir / "points", error);
  for (std::size_t i = 0; i < spec.points.size(); ++i) {
    WriteFileAtomic(dir / "points" / (spec.points[i].id + ".yaml"), point_yaml[i]);
  }
  // Each run from the first folder that finished it, else the first that recorded a failure
  // (RequireCompleteMerge has made sure that one of them does).
  int copied = 0;
  for (const StudyPoint& point : spec.points) {
    for (int i = 0; i < spec.runs; ++i) {
      const std::uint64_t seed = spec.first_seed + static_cast<std::uint64_t>(i);
      const fs::path target = RunFolder(dir, point.id, seed);
      if (fs::is_regular_file(target / "metrics.json", error)) continue;  // resumed merge
      const auto finished = std::find_if(
          request.merge_dirs.begin(), request.merge_dirs.end(), [&](const fs::path& d) {
            return fs::is_regular_file(RunFolder(d, point.id, seed) / "metrics.json", error);
          });
      if (finished != request.merge_dirs.end()) {
        const fs::path source = RunFolder(*finished, point.id, seed);
        const fs::path staging = target.string() + ".merging";
        fs::remove_all(staging, error);
        fs::create_directories(staging.parent_path(), error);
        // Links are copied as links: a link in a folder to merge is never followed (one to "/"
        // would copy the file system).
        fs::copy(source, staging, fs::copy_options::recursive | fs::copy_options::copy_symlinks,
                 error);
        if (error) {
          throw std::runtime_error("cannot copy '" + source.string() + "': " + error.message());
        }
        fs::remove_all(target, error);  // an unfinished leftover of a resumed merge
        fs::rename(staging, target, error);
        if (error) {
          throw std::runtime_error("cannot move '" + staging.string() + "' to '" + target.string() +
                                   "': " + error.message());
        }
        ++copied;
        continue;
      }
      for (const fs::path& d : request.merge_dirs) {
        const fs::path status = StatusFile(d, point.id, seed);
        if (RecordedFailure(status)) {
          fs::create_directories(StatusFile(dir, point.id, seed).parent_path(), error);
          WriteFileAtomic(StatusFile(dir, point.id, seed), ReadRegularFile(status, kMaxPlanBytes));
          break;
        }
      }
    }
  }
  std::printf("study merge: %zu folder(s), %d run folder(s) copied into %s\n",
              request.merge_dirs.size(), copied, dir.string().c_str());
  json timing;
  timing["merged_folders"] = request.merge_dirs.size();
  timing["runs_copied"] = copied;
  return FinishStudy(spec, dir, request, std::move(timing));
}

}  // namespace corridorsim
