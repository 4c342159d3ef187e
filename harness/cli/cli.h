#pragma once
// The `corridorsim` command line. ParseCommandLine turns the arguments into what to do: which job
// with which request, or the help text to print. It is a pure function (no file is read, written
// or looked at, nothing runs), so that it can be unit-tested and fuzzed (fuzz/cli_fuzzer.cpp);
// main.cpp only dispatches. Every number is parsed strictly: decimal only, no wrap-around, no
// trailing characters, no inf or nan, magnitudes bounded.

#include <cstdint>
#include <string>
#include <vector>

#include "harness/evaluate/evaluate_request.h"
#include "harness/run/drive.h"
#include "harness/run/run.h"
#include "harness/run/snapshot.h"
#include "harness/run/where.h"
#include "harness/scenario/job.h"
#include "harness/study/study.h"
#include "harness/study/suite.h"
#include "harness/workbench/dataset_request.h"
#include "harness/workbench/detect.h"
#include "harness/workbench/score_request.h"
#include "harness/workbench/train_detectors_request.h"

namespace corridorsim {

/// Exit codes of `corridorsim` (the help footers and README list them). When several apply, the
/// first of 1 (failure), 2 (bad input), 3 (expectation failed), 4 (extra failed) that happened
/// wins: bad input and failures stop a job before its results are written; 3 takes precedence
/// over 4.
inline constexpr int kExitSuccess = 0;
inline constexpr int kExitFailure = 1;   // anything else (e.g. no GL context, disk full)
inline constexpr int kExitBadInput = 2;  // one message: `file:line:column: key: ...` or
                                         // `command line: --flag: ...`; nothing is written
// kExitExpectationsFailed = 3 (harness/run/run.h); kExitExtraFailed = 4 (harness/run/run.h).

/// Bounds of `snapshot --pose`: |x|, |y| in metres and |yaw| in degrees.
inline constexpr double kPoseMaxAbsMetres = 100000.0;
inline constexpr double kPoseMaxAbsYawDeg = 360.0;

/// What the command line asks for.
struct CommandLine {
  enum class Job {
    kHelp,
    kWorld,
    kSnapshot,
    kRun,
    kReplay,  // `replay`: RunScenario with run.replay set (no default scenario)
    kDrive,
    kWhere,
    kDetect,
    kTrainDetectors,
    kDataset,
    kScore,
    kStudy,
    kStudyMerge,
    kTest,
    kVersion,  // --version
    kPlugin,   // plugin LIB
    kEvaluate,
  };
  Job job = Job::kHelp;
  std::string help_text;  // kHelp: printed on stdout, exit 0
  // The request of `job`. An empty scenario_file means "none given": main picks the default
  // scenario and says which file it used.
  JobRequest world;
  SnapshotRequest snapshot;
  RunRequest run;
  DriveRequest drive;
  WhereRequest where;
  DetectRequest detect;
  TrainDetectorsRequest train_detectors;
  DatasetRequest dataset;
  ScoreRequest score;
  StudyRequest study;  // kStudy and kStudyMerge
  TestRequest test;
  std::string plugin_file;  // kPlugin
  EvaluateRequest evaluate;
};

/// Parses the arguments (without the program name). Throws InputError at
/// `command line: <flag>: <message>` for anything it cannot accept, and nothing else.
CommandLine ParseCommandLine(const std::vector<std::string>& args);

/// A seed: a decimal integer in [0, 2^64 - 1] without sign, leading zeros or anything else.
/// Throws InputError naming `flag`.
std::uint64_t ParseSeedArgument(const std::string& text, const std::string& flag);

/// A decimal number (`12`, `-0.5`, `1e3`; no hex, inf, nan, spaces or trailing characters) with
/// |value| <= max_abs. Throws InputError naming `flag`.
double ParseNumberArgument(const std::string& text, double max_abs, const std::string& flag);

/// `where ROOM`: 1 to kMaxRoomChars printable ASCII characters without spaces (as a semantic map
/// holds them). Throws InputError naming `flag`.
inline constexpr std::size_t kMaxRoomChars = 32;
std::string ParseRoomArgument(const std::string& text, const std::string& flag);
/// `where --pipeline NAME`: 1 to kMaxPipelineChars letters, digits, '_' or '-' (it names a file).
inline constexpr std::size_t kMaxPipelineChars = 64;
std::string ParsePipelineArgument(const std::string& text, const std::string& flag);
/// Bounds of `train-detectors`' counts (training must take minutes on two cores).
inline constexpr int kMaxTrainWorlds = 200;
inline constexpr int kMaxViewsPerWorld = 500;

/// `score --expect KEY OP VALUE`: KEY is `<class>.<metric>` (kScoreClassNames,
/// kScoreMetricNames), OP one of >=, >, <=, <, VALUE a decimal number. Throws InputError naming
/// `flag`.
ScoreExpectation ParseScoreExpectation(const std::string& text, const std::string& flag);

/// `snapshot --pose x,y,yaw`: metres, metres, degrees, each within the bounds above.
struct PoseArgument {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_deg = 0.0;
};
PoseArgument ParsePoseArgument(const std::string& text, const std::string& flag);

}  // namespace corridorsim
