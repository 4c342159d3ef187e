#pragma once
// What the study's files share, internal to harness/study/: study_plan.cpp (the plan and the
// preparation of a study), study_folder.cpp (the folder's layout, its preparation and what it
// records), study_run.cpp (`study`: the runs J at a time), study_merge.cpp (`study merge`),
// study_finish.cpp (the summary, report and exit code of both), slurm.cpp (`study --slurm`) and
// study_reuse.cpp (one recording a seed, replayed for the other points).

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/io/child_process.h"
#include "harness/study/study.h"
#include "harness/study/study_file.h"
#include "harness/study/study_summary.h"

namespace corridorsim::study_internal {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

/// The largest study.json read back (a plan of kMaxSweepPoints points is far below it).
inline constexpr std::uint64_t kMaxPlanBytes = std::uint64_t{64} << 20;

// study_folder.cpp: the study folder.

/// runs/<point>/seed_<S>, status/<point>/seed_<S>.json, logs/<point>/seed_<S>.log of `dir`.
fs::path RunFolder(const fs::path& dir, const std::string& point, std::uint64_t seed);
fs::path StatusFile(const fs::path& dir, const std::string& point, std::uint64_t seed);
fs::path LogFile(const fs::path& dir, const std::string& point, std::uint64_t seed);

/// Prepares the study folder `dir` for the plan `plan_text`: new (created with its marker), the
/// same study (resumed), or with `force` an earlier corridorsim output (removed first). Anything
/// else is bad input (InputError naming `option`).
void PrepareFolder(const fs::path& dir, const std::string& plan_text, bool force,
                   const std::string& option);

/// Every planned run's outcome as the folder records it: finished when its run folder has
/// metrics.json, failed or timed out when its status says so, else not run.
std::vector<StudyRunRecord> CollectRecords(const StudySpec& spec, const fs::path& dir);

// study_plan.cpp: the plan (study.json) and the preparation of a study.

/// What differs between two plans' plugin libraries ("" when nothing): the merge names it.
std::string PluginDifference(const json& a, const json& b);

/// The summary's view of a plan (for `merge`, which has the folders, not the study file);
/// InputError naming `file` when it is not a plan of this build or out of bounds.
StudySpec SpecFromPlan(const json& plan, const fs::path& file);

/// The plan in `file` (InputError when it is not JSON).
json ReadPlan(const fs::path& file);

/// One run of the plan: a point and a seed.
struct PlannedRun {
  std::size_t point;
  std::uint64_t seed;
};

// study_reuse.cpp: one sensor stream for every point (docs/studies.md, "Replay instead of
// rendering").

/// Whether a study's points read one sensor stream: their resolved scenarios (`point_yaml`) are
/// equal outside what a replay may change (record::FirstStreamDifference: pipelines,
/// expectations, name, description) and their pipelines read the same cameras (a recording holds
/// the cameras its run rendered). `why`: the first reason they do not.
struct StreamSharing {
  bool shared = false;
  std::string why;
};
StreamSharing DecideStreamSharing(const StudySpec& spec,
                                  const std::vector<std::string>& point_yaml);

/// The study loaded, its folder prepared (plan, points, shard) and the runs this shard still has
/// to run.
struct PreparedStudy {
  StudySpec spec;
  fs::path dir;
  std::vector<PlannedRun> todo;
  std::size_t planned_here = 0;
  std::size_t already = 0;
  // Whether the points share one sensor stream (asked only for a local study with replay on).
  StreamSharing stream;
};

/// Loads the study, checks and prepares its folder (InputError before anything is written).
PreparedStudy PrepareStudy(const StudyRequest& request);

/// How one run gets its sensor stream.
struct RunStream {
  enum class Kind {
    kLive,    // `run`: simulated and rendered
    kRecord,  // `run --record`: simulated and rendered, recorded for the seed's other points
    kReplay,  // `replay <recording>`: another point's recording of the same seed
  };
  Kind kind = Kind::kLive;
  bool record_requested = false;  // the study's --record: a recording in every run folder
  fs::path recording;             // kReplay: the recording it replays
};

/// What the run's status file says of its stream: "live", "recorded" (--record), "recorded for
/// replay", "replayed from runs/<point>/seed_<S>/recording.mcap".
std::string StreamText(const RunStream& stream, const fs::path& dir);

/// The runs of a study in the order they may start. With `share` (DecideStreamSharing), the first
/// run of each seed records (unless a finished run of the seed left its recording: a resumed
/// study) and the seed's other runs replay it once it finished; a recording run that fails leaves
/// the others to render live. When a seed's replays are done its recording is removed (without
/// the study's --record, `record`), so the folders hold what they hold without replay. A seed
/// with a single run left renders it.
class RunQueue {
 public:
  RunQueue(const StudySpec& spec, const fs::path& dir, const std::vector<PlannedRun>& todo,
           bool share, bool record);
  /// The next run that may start now (replays whose recording is ready first, then the runs that
  /// render, in plan order), or nothing: every run started, or the rest wait for a recording.
  std::optional<std::pair<PlannedRun, RunStream>> Next();
  /// A started run ended; `finished`: it wrote results (RecordRun's "finished").
  void Ended(const PlannedRun& run, bool finished);
  /// Every run was started.
  bool empty() const { return started_ == entries_.size(); }

 private:
  static constexpr std::size_t kNoGroup = static_cast<std::size_t>(-1);
  struct Entry {
    PlannedRun run;
    RunStream stream;
    std::size_t group = kNoGroup;  // its seed's recording, when it takes part in one
    bool started = false;
  };
  // The runs of one seed that share its recording.
  struct Group {
    enum class State { kWaiting, kReady, kLive };
    std::uint64_t seed = 0;
    State state = State::kWaiting;
    fs::path recording;
    std::size_t replays_left = 0;
    bool remove_after = false;  // remove the recording after the last replay
  };
  const StudySpec& spec_;
  fs::path dir_;
  std::vector<Entry> entries_;
  std::vector<Group> groups_;
  std::size_t started_ = 0;
};

// study_run.cpp: the runs.

/// Seconds since `since`.
double Seconds(Clock::time_point since);

/// Starts one run: `<program> run <point scenario> --seed S --out runs/<point>/seed_S` (with
/// --record for kRecord or the study's --record), or for kReplay `<program> replay <recording>
/// <point scenario> --seed S --out runs/<point>/seed_S`.
std::unique_ptr<ChildProcess> StartRun(const std::string& program, const StudySpec& spec,
                                       const fs::path& dir, const PlannedRun& run,
                                       const RunStream& stream, bool viewer);

/// How a run ended, recorded in status/<point>/seed_<S>.json (and returned), with its stream
/// (StreamText).
json RecordRun(const StudySpec& spec, const fs::path& dir, const PlannedRun& run,
               const ChildStatus& status, bool timed_out, double elapsed, double peak_rss_mib,
               const std::string& stream);

// study_finish.cpp: the end of a study or a merge.

/// " --may-diverge a,b" as given, or "".
std::string MayDivergeArgument(const StudyRequest& request);

/// Writes the summary files, the report and the plots of the runs in `dir`, with `timing` (the
/// caller's part of timing.json); prints the closing table. Returns the exit code (RunStudy's).
int FinishStudy(const StudySpec& spec, const fs::path& dir, const StudyRequest& request,
                json timing);

}  // namespace corridorsim::study_internal
