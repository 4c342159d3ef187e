// The `run` subcommand: a scenario closed loop, every pipeline scored, the run folder written.
#include <memory>
#include <string>

#include "harness/cli/options.h"
#include "harness/cli/subcommands.h"
#include "slam/registry.h"

namespace corridorsim::cli {
namespace {

// `run --help`'s list of the shipped pipeline types (slam/registry.h).
std::string PipelineListFooter() {
  std::string names;
  for (const std::string& n : slam::PipelineNames()) names += (names.empty() ? "" : ", ") + n;
  return "Pipelines (under `pipelines:`, docs/scenarios.md; P1's: docs/p1.md): " + names + ".\n";
}

// --record and its options, on `run` and `replay` (docs/recordings.md).
struct RecordOptions {
  OptionalArgument topics, compression;
  void Add(CLI::App* job, CommandLine* parsed) {
    AddSwitch(job, "--record", parsed->run.record,
              "Also write recording.mcap in the run folder: every sensor, the truth, the "
              "estimates and the world as ROS 2 messages (MCAP; Foxglove, Lichtblick, Rerun, "
              "ros2 bag play: docs/recordings.md); `corridorsim replay` runs pipelines on it");
    AddSwitch(job, "--record-bag", parsed->run.record_bag,
              "Also write recording.bag in the run folder: the same topics as a ROS 1 bag "
              "(rosbag, rqt_bag, evo: docs/recordings.md); with or without --record");
    AddOption(job, "--record-topics", topics,
              "Record only the topics matching these comma-separated patterns ('*' matches any "
              "characters), e.g. '/front/*,/tf*'",
              "PATTERNS");
    AddOption(job, "--record-compression", compression,
              "The recording's chunk compression: zstd (default), lz4 or none", "NAME");
  }
  void Resolve(RunRequest* run) const {
    if (topics.given()) {
      if (!run->record && !run->record_bag)
        Fail("--record-topics", "needs --record or --record-bag");
      run->record_topics = topics.text;
    }
    if (compression.given()) {
      if (!run->record) Fail("--record-compression", "needs --record");
      if (compression.text != "zstd" && compression.text != "lz4" && compression.text != "none") {
        Fail("--record-compression", "must be zstd, lz4 or none " + Got(compression.text));
      }
      run->record_compression = compression.text;
    }
  }
};

class RunCommand final : public Subcommand {
 public:
  RunCommand(CLI::App* app, CommandLine* parsed)
      : Subcommand(
            app, "run",
            "Run a scenario closed loop, score every pipeline against ground truth, write the "
            "run"),
        options_(job_, "out/run", std::string("Scenario YAML ") + kDefaultScenarioHelp,
                 "Seed of every random stream of the run", "Run folder") {
    AddOption(job_, "--export", export_,
              "Also write a dataset into this folder (outside the run folder): TUM RGB-D "
              "(front), EuRoC/ASL (upward, lateral), odometry CSV, labels and COCO plate "
              "boxes (docs/export.md); staged and replaced like --out");
    AddSwitch(job_, "--no-plots", no_plots_, "Skip plots/ (matplotlib)");
    AddSwitch(job_, "--no-viewer", no_viewer_, "Skip viewer.html (docs/viewer.md)");
    AddSwitch(job_, "--keep-frames", parsed->run.keep_frames,
              "Keep downscaled JPEGs of the rendered frames in frames/ for viewer.html "
              "(within --keep-frames-mb)");
    AddOption(job_, "--keep-frames-mb", keep_frames_mb_,
              "The most frames/ may hold, MB (1-40, default 20): past it every other kept "
              "frame is dropped and the stride doubles");
    record_.Add(job_, parsed);
    AddSwitch(job_, "--check", parsed->run.check_only,
              "Only check the scenario: load it, build its world, path and pipelines, and exit");
    SetFooter(
        job_,
        "Writes the results first: scenario.yaml (resolved, with the seed), world.json, "
        "ground_truth.tum (the planar truth at 100 Hz and every odometry stamp, as drive "
        "writes it), <pipeline>.tum, <pipeline>_cov.txt (ov_eval), "
        "<pipeline>_errors.csv, <pipeline>_nis.csv, <pipeline>_landmarks.json, "
        "<pipeline>_detections.csv, "
        "metrics.json (docs/metrics.md), timing.json, events.json, "
        "provenance.json (what the bytes depend on: build, compiler, Mesa, backend); then "
        "the extras: maps/, the --export dataset, plots/ (python3 scripts/plot_run.py), "
        "viewer.html (scripts/make_viewer.py: one page, offline, docs/viewer.md).\n" +
            PipelineListFooter(),
        FolderFooter::kStaged,
        "0 success; 5 a pipeline failed (it alone: the run went on and the other "
        "pipelines' results are written; the reason is on stderr and in events.json); 3 an "
        "expectation failed; 4 the results are written but an extra (maps/, plots/, viewer.html, "
        "the --export dataset) failed (its message is on stderr); 5 takes precedence over 3, 3 "
        "over 4; 2 bad input (nothing is written); 1 other failures (the previous folder is left "
        "as it was).");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kRun;
    options_.Resolve(&parsed->run);
    if (export_.given()) parsed->run.export_dir = FolderName(export_.text, "--export");
    parsed->run.plots = !no_plots_;
    parsed->run.viewer = !no_viewer_;
    record_.Resolve(&parsed->run);
    if (keep_frames_mb_.given()) {
      const double mb = ParseNumberArgument(keep_frames_mb_.text, 1e6, "--keep-frames-mb");
      if (!(mb >= 1.0 && mb <= 40.0))
        Fail("--keep-frames-mb", "must be in [1, 40] " + Got(keep_frames_mb_.text));
      if (!parsed->run.keep_frames) Fail("--keep-frames-mb", "needs --keep-frames");
      parsed->run.keep_frames_budget_mb = mb;
    }
  }

 private:
  JobOptions options_;
  OptionalArgument export_, keep_frames_mb_;
  RecordOptions record_;
  bool no_plots_ = false, no_viewer_ = false;
};

class ReplayCommand final : public Subcommand {
 public:
  ReplayCommand(CLI::App* app, CommandLine* parsed)
      : Subcommand(app, "replay",
                   "Run pipelines on a recording (no physics, no rendering) and write the run "
                   "folder a live run would"),
        recording_(AddOption(job_, "recording", recording_text_,
                             "The recording (recording.mcap of `run --record`)", "RECORDING")
                       ->required()),
        options_(job_, "out/replay",
                 "Scenario YAML with the pipelines to run (default: the recording's own); its "
                 "world, robot, path and sensors must be the recording's",
                 "The recording's seed (a replay cannot change it)", "Run folder") {
    AddSwitch(job_, "--no-plots", no_plots_, "Skip plots/ (matplotlib)");
    AddSwitch(job_, "--no-viewer", no_viewer_, "Skip viewer.html (docs/viewer.md)");
    record_.Add(job_, parsed);
    SetFooter(job_,
              "Writes the run folder `corridorsim run` writes (docs/recordings.md): for the same "
              "pipelines and options, metrics.json and every trajectory are the live run's, "
              "byte for byte. A pipeline that reads a sensor the recording lacks, a scenario "
              "whose stream differs from the recording's (the first difference is named), and a "
              "truncated or corrupt recording (the record and byte offset are named) are bad "
              "input.\n",
              FolderFooter::kStaged,
              "as `run`: 0 success; 5 a pipeline failed; 3 an expectation failed; 4 an extra "
              "failed; 2 bad input (nothing is written); 1 other failures.");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kReplay;
    options_.Resolve(&parsed->run);
    parsed->run.replay = FileName(recording_text_, "RECORDING");
    parsed->run.plots = !no_plots_;
    parsed->run.viewer = !no_viewer_;
    record_.Resolve(&parsed->run);
  }

 private:
  std::string recording_text_;
  CLI::Option* recording_;
  JobOptions options_;
  RecordOptions record_;
  bool no_plots_ = false, no_viewer_ = false;
};

}  // namespace

std::unique_ptr<Subcommand> AddRunCommand(CLI::App* app, CommandLine* parsed) {
  return std::make_unique<RunCommand>(app, parsed);
}

std::unique_ptr<Subcommand> AddReplayCommand(CLI::App* app, CommandLine* parsed) {
  return std::make_unique<ReplayCommand>(app, parsed);
}

}  // namespace corridorsim::cli
