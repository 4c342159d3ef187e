// The subcommands about other systems: evaluate (their trajectories and maps against a run's
// truth) and plugin (a pipeline plugin library and what it registers).
#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "harness/cli/options.h"
#include "harness/cli/subcommands.h"

namespace corridorsim::cli {
namespace {

// `--estimate NAME=FILE` and the like: at most kMaxEvaluatedFiles, each NAME a pipeline name
// given once, each FILE not empty.
std::vector<EvaluateRequest::NamedFile> NamedFiles(const std::vector<std::string>& texts,
                                                   const std::string& flag) {
  if (texts.size() > kMaxEvaluatedFiles) {
    Fail(flag, "at most " + std::to_string(kMaxEvaluatedFiles) + " files");
  }
  std::vector<EvaluateRequest::NamedFile> files;
  for (const std::string& text : texts) {
    const std::size_t eq = text.find('=');
    if (eq == std::string::npos) Fail(flag, "expected NAME=FILE " + Got(text));
    EvaluateRequest::NamedFile f{ParsePipelineArgument(text.substr(0, eq), flag),
                                 text.substr(eq + 1)};
    if (f.file.empty()) Fail(flag, "an empty file name " + Got(text));
    for (const auto& other : files) {
      if (other.name == f.name) Fail(flag, "the name '" + f.name + "' is given twice");
    }
    files.push_back(std::move(f));
  }
  return files;
}

class EvaluateCommand final : public Subcommand {
 public:
  explicit EvaluateCommand(CLI::App* app)
      : Subcommand(app, "evaluate",
                   "Score trajectories and landmark maps of any system against a run's truth") {
    AddOption(job_, "run", run_,
              "The run folder (corridorsim run --out): its ground_truth.tum and world.json",
              "RUN_DIR")
        ->required();
    AddOption(job_, "--estimate", estimates_,
              "A trajectory: TUM (t tx ty tz qx qy qz qw) or OpenVINS ov_eval with "
              "covariances (20 columns) of world_from_robot (repeatable)",
              "NAME=FILE");
    AddOption(job_, "--landmarks", landmarks_,
              "A landmark map in <pipeline>_landmarks.json's format, in the frame of the "
              "estimate of the same NAME (aligned with it) (repeatable)",
              "NAME=FILE");
    AddOption(job_, "--frame", frames_,
              "The estimate NAME's poses are of this camera's optical frame (world_from_"
              "camera, as the TUM RGB-D export's groundtruth.txt): scored as world_from_robot "
              "through the run's mount (default: the robot frame)",
              "NAME=CAMERA");
    AddOption(job_, "--align", align_,
              "Fit before scoring: none, se2 (yaw + x-y), se3, sim3 (with scale: monocular)",
              "none|se2|se3|sim3")
        ->capture_default_str();
    AddOption(job_, "--max-dt", max_dt_,
              "Largest stamp difference to a truth pose for a pose to be "
              "scored, s (default 0.01, as evo's; at most 1)",
              "S");
    AddOutFolder(job_, out_, "Output folder (default: RUN_DIR/evaluation)", "DIR");
    AddSwitch(job_, "--force", force_, "Replace a non-empty output folder");
    AddOption(job_, "--expect", expect_,
              "A check such as mine.ate_rmse_m<0.2 or mine.map.lamp.rmse_m<=0.1 (repeatable)",
              "NAME.METRIC<VALUE");
    AddSwitch(job_, "--no-plots", no_plots_, "Skip plots/ (matplotlib)");
    SetFooter(job_,
              "Writes evaluation.json (per NAME: the trajectory metrics of metrics.json after the "
              "alignment, NEES where the file has covariances, map.<type> for --landmarks, "
              "align.* and the evaluation's own metrics), <NAME>_aligned.tum, <NAME>_errors.csv "
              "and plots/ (docs/evaluation.md).\n",
              FolderFooter::kNone,
              "0 success, 3 an --expect check failed, 4 the results are written but plots/ "
              "failed, 2 bad input (the file, line and column, or the flag, are named), 1 other "
              "failures.");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kEvaluate;
    EvaluateRequest& r = parsed->evaluate;
    r.run_dir = FolderName(run_, "RUN_DIR");
    if (estimates_.empty() && landmarks_.empty()) {
      Fail("--estimate", "nothing to evaluate: give --estimate NAME=FILE or --landmarks NAME=FILE");
    }
    r.estimates = NamedFiles(estimates_, "--estimate");
    r.landmarks = NamedFiles(landmarks_, "--landmarks");
    for (const EvaluateRequest::NamedFile& f : NamedFiles(frames_, "--frame")) {
      const bool estimated = std::any_of(r.estimates.begin(), r.estimates.end(),
                                         [&](const auto& e) { return e.name == f.name; });
      if (!estimated) Fail("--frame", "'" + f.name + "' is no --estimate name");
      r.frames.push_back({f.name, ParsePipelineArgument(f.file.string(), "--frame")});
    }
    const std::optional<evaluate::Alignment> alignment = evaluate::AlignmentFromName(align_);
    if (!alignment) Fail("--align", "expected none, se2, se3 or sim3 " + Got(align_));
    r.alignment = *alignment;
    if (max_dt_.given()) {
      r.max_dt_s = ParseNumberArgument(max_dt_.text, kMaxAssociationSeconds, "--max-dt");
      if (r.max_dt_s < 0.0) Fail("--max-dt", "must not be negative " + Got(max_dt_.text));
    }
    if (out_.given()) r.out_dir = FolderName(out_.text, "--out");
    r.force = force_;
    r.plots = !no_plots_;
    if (expect_.size() > 256) Fail("--expect", "at most 256 checks");
    r.expectations = expect_;
  }

 private:
  std::string run_, align_ = "none";
  OptionalArgument max_dt_, out_;
  std::vector<std::string> estimates_, landmarks_, expect_, frames_;
  bool force_ = false, no_plots_ = false;
};

class PluginCommand final : public Subcommand {
 public:
  explicit PluginCommand(CLI::App* app)
      : Subcommand(app, "plugin",
                   "Load a pipeline plugin library and print what it registers (docs/plugins.md)") {
    AddOption(job_, "library", file_, "The plugin library (a .so file)", "LIB")->required();
    SetFooter(job_,
              "Prints the plugin's name, version, the corridorsim version it was built against, "
              "its file and SHA-256, then each pipeline type it registers with its options (key, "
              "unit, default, bounds, meaning) as docs/scenarios.md shows the shipped ones.\n",
              FolderFooter::kNone,
              "0 success; 2 the library cannot be loaded as a plugin (missing, not a regular "
              "file, dlopen's error, no entry point, another SDK ABI, a taken type name).");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kPlugin;
    parsed->plugin_file = FileName(file_, "library");
  }

 private:
  std::string file_;
};

}  // namespace

std::unique_ptr<Subcommand> AddEvaluateCommand(CLI::App* app) {
  return std::make_unique<EvaluateCommand>(app);
}
std::unique_ptr<Subcommand> AddPluginCommand(CLI::App* app) {
  return std::make_unique<PluginCommand>(app);
}

}  // namespace corridorsim::cli
