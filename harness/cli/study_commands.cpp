// The subcommands of many runs: study (with `study merge`) and test.
#include <memory>
#include <string>
#include <vector>

#include "harness/cli/options.h"
#include "harness/cli/subcommands.h"
#include "harness/scenario/overrides.h"
#include "harness/study/study_file.h"

namespace corridorsim::cli {
namespace {

class StudyCommand final : public Subcommand {
 public:
  explicit StudyCommand(CLI::App* app)
      : Subcommand(
            app, "study",
            "Run a scenario over many seeds (and sweep points) and aggregate the statistics"),
        options_(job_, "out/study",
                 "Study YAML (a scenario with a `study:` section, docs/studies.md) or a "
                 "plain scenario file",
                 "First seed (run i uses seed + i; default: study.first_seed, else the "
                 "scenario's seed)",
                 "Study folder (resumed when it holds the same study)") {
    AddOption(job_, "--runs", runs_, "Seeds per sweep point (default: study.runs, 10)", "N");
    AddOption(job_, "--jobs", jobs_, "Worker processes (default: the number of cores)", "J");
    AddOption(job_, "--shard", shard_,
              "Run only part K of N (run k of the plan belongs to part k mod N); "
              "`study merge` combines the parts",
              "K/N");
    AddOption(job_, "--may-diverge", may_diverge_,
              "Pipelines whose diverged runs do not fail the study (added to the "
              "scenario's baseline: true pipelines and study.may_diverge)",
              "PIPELINE[,PIPELINE]")
        ->delimiter(',');
    AddSwitch(job_, "--no-plots", no_plots_, "Skip plots/ (matplotlib)");
    AddSwitch(job_, "--no-viewer", no_viewer_,
              "Skip report.html and each run's viewer.html (docs/viewer.md)");
    AddSwitch(job_, "--record", record_,
              "Also write recording.mcap in every run folder (`run --record`, "
              "docs/recordings.md)");
    AddSwitch(job_, "--no-replay", no_replay_,
              "Render every run, even when the points differ only in their pipelines (by "
              "default each seed is then rendered once and replayed for the other points)");
    AddSwitch(job_, "--slurm", slurm_,
              "Write a Slurm job array (one task per shard) and a merge job into <out>/slurm/ "
              "instead of running here (one run is run here first to measure the cost)");
    AddSwitch(job_, "--submit", submit_, "With --slurm: submit both jobs with sbatch");
    AddOption(job_, "--slurm-tasks", slurm_tasks_,
              "With --slurm: the number of array tasks (default: from the measured cost)", "N");
    AddOption(job_, "--slurm-task-minutes", task_minutes_,
              "With --slurm: the run time a task packs (default 60)", "MIN");
    merge_ = job_->add_subcommand(
        "merge", "Combine study folders of one plan (shards) into one study folder and summary");
    AddOption(merge_, "dirs", merge_dirs_, "Study folders to combine")->required();
    AddOutFolder(merge_, merge_out_, "The combined study folder");
    AddSwitch(merge_, "--force", merge_force_,
              "Replace a non-empty --out folder written by corridorsim");
    AddSwitch(merge_, "--no-plots", merge_no_plots_, "Skip plots/ (matplotlib)");
    AddSwitch(merge_, "--no-viewer", merge_no_viewer_, "Skip report.html (docs/viewer.md)");
    SetFooter(job_,
              "Each run is `corridorsim run <point scenario> --seed S --no-plots` in a process of "
              "its own (when the points differ only in their pipelines, a seed's first run adds "
              "--record and its other runs are `corridorsim replay` of that recording: the same "
              "files, without rendering again; the recording is removed afterwards unless "
              "--record); finished runs are kept (runs/<point>/seed_<S>/, each with its "
              "viewer.html) and skipped when the same study is run again. Writes study.json (the "
              "plan), points/, runs/, status/, logs/, summary.json, summary.csv, paired.csv, "
              "report.md, timing.json, plots/ (docs/studies.md) and report.html "
              "(docs/viewer.md).\n",
              FolderFooter::kNone,
              "0 success; 1 a run failed or timed out, or a pipeline that is neither a "
              "baseline nor in may_diverge diverged (the others are summarised, each one named); "
              "3 a study expectation failed; 4 only plots/ or report.html failed; 2 bad input "
              "(nothing runs), or `study merge` folders that lack runs of the plan (nothing is "
              "written). Ctrl-C or SIGTERM stops the runs in flight too; the same command "
              "resumes the study.");
  }

  void Resolve(CommandLine* parsed) const override {
    if (merge_->parsed()) {
      ResolveMerge(parsed);
      return;
    }
    parsed->job = CommandLine::Job::kStudy;
    StudyRequest& r = parsed->study;
    options_.Resolve(&r);
    if (runs_.given()) r.runs = WholeArgument(runs_.text, kMaxStudyRuns, "--runs");
    if (jobs_.given()) r.jobs = WholeArgument(jobs_.text, kMaxStudyJobs, "--jobs");
    if (shard_.given()) {
      const std::string& shard = shard_.text;
      const std::size_t slash = shard.find('/');
      if (slash == std::string::npos) Fail("--shard", "expected K/N, e.g. 2/8 " + Got(shard));
      const int k = WholeArgument(shard.substr(0, slash), kMaxShards, "--shard");
      const int n = WholeArgument(shard.substr(slash + 1), kMaxShards, "--shard");
      if (k > n) Fail("--shard", "K must lie in [1, N] " + Got(shard));
      r.shard_index = k - 1;
      r.shard_count = n;
    }
    r.plots = !no_plots_;
    r.viewer = !no_viewer_;
    r.record = record_;
    r.replay = !no_replay_;
    if (may_diverge_.size() > 64) Fail("--may-diverge", "at most 64 pipelines");
    r.may_diverge = may_diverge_;
    r.slurm = slurm_;
    r.submit = submit_;
    if (submit_ && !slurm_) Fail("--submit", "only with --slurm");
    if (slurm_tasks_.given()) {
      if (!slurm_) Fail("--slurm-tasks", "only with --slurm");
      r.slurm_tasks = WholeArgument(slurm_tasks_.text, kMaxSlurmTasks, "--slurm-tasks");
    }
    if (task_minutes_.given()) {
      if (!slurm_) Fail("--slurm-task-minutes", "only with --slurm");
      r.slurm_task_minutes = WholeArgument(task_minutes_.text, 100000, "--slurm-task-minutes");
    }
    if (slurm_ && shard_.given()) {
      Fail("--shard", "--slurm writes the shards itself");
    }
  }

 private:
  // `study merge DIR...`
  void ResolveMerge(CommandLine* parsed) const {
    parsed->job = CommandLine::Job::kStudyMerge;
    StudyRequest& r = parsed->study;
    FolderName(merge_out_, "--out");
    if (merge_dirs_.size() > static_cast<std::size_t>(kMaxShards)) {
      Fail("dirs", "at most " + std::to_string(kMaxShards) + " folders");
    }
    for (const std::string& d : merge_dirs_) r.merge_dirs.emplace_back(FolderName(d, "dirs"));
    r.out_dir = merge_out_;
    r.force = merge_force_;
    r.plots = !merge_no_plots_;
    r.viewer = !merge_no_viewer_;
  }

  JobOptions options_;
  OptionalArgument runs_, jobs_, shard_, slurm_tasks_, task_minutes_;
  std::vector<std::string> may_diverge_;
  bool no_plots_ = false, no_viewer_ = false, slurm_ = false, submit_ = false;
  bool record_ = false, no_replay_ = false;
  CLI::App* merge_ = nullptr;
  std::vector<std::string> merge_dirs_;
  std::string merge_out_ = "out/study_merged";
  bool merge_force_ = false, merge_no_plots_ = false, merge_no_viewer_ = false;
};

class TestCommand final : public Subcommand {
 public:
  explicit TestCommand(CLI::App* app)
      : Subcommand(app, "test",
                   "Run scenarios and studies as a test suite and write a JUnit XML report") {
    AddOption(job_, "files", files_,
              "Scenario or study files (default: ./scenarios/default.yaml if it exists, "
              "else the shipped one)");
    AddOutFolder(job_, out_, "Folder of the runs and studies (one folder per file)");
    AddOption(job_, "--junit", junit_, "Write the JUnit XML report to this file", "FILE");
    AddOption(job_, "--jobs", jobs_,
              "Files run at once, each its own `corridorsim run` or `study` (default 1, "
              "at most 256; a study's runs then share the cores); the report is the "
              "same for any count but for its `time` attributes",
              "J");
    AddSwitch(job_, "--record", record_,
              "Also write recording.mcap in every run folder (passed to each `run` and `study`)");
    AddSetOption(job_, &settings_);
    SetFooter(job_,
              "Each expectation of a scenario (or each study expectation at each sweep point) is "
              "one test case; a failure gives the measured value and the threshold, system-out "
              "the run's viewer.html (a study's report.html; the folder with --no-viewer) as "
              "[[ATTACHMENT|path]]; a run that cannot finish is an error case with its log's "
              "tail (docs/ci.md).\n",
              FolderFooter::kNone,
              "0 every case passed; 3 an expectation failed; 1 a run or study could not "
              "finish; 2 bad input (nothing runs).");
  }

  void Resolve(CommandLine* parsed) const override {
    parsed->job = CommandLine::Job::kTest;
    TestRequest& r = parsed->test;
    if (files_.size() > static_cast<std::size_t>(kMaxSuiteFiles)) {
      Fail("files", "at most " + std::to_string(kMaxSuiteFiles) + " files");
    }
    for (const std::string& f : files_) FileName(f, "files");
    r.files = files_;
    r.out_dir = FolderName(out_, "--out");
    if (junit_.given()) r.junit_file = FileName(junit_.text, "--junit");
    if (jobs_.given()) r.jobs = WholeArgument(jobs_.text, kMaxSuiteJobs, "--jobs");
    ParseSettings(settings_);
    r.settings = settings_;
    r.record = record_;
  }

 private:
  std::vector<std::string> files_;
  bool record_ = false;
  std::string out_ = "out/test";
  OptionalArgument junit_, jobs_;
  std::vector<std::string> settings_;
};

}  // namespace

std::unique_ptr<Subcommand> AddStudyCommand(CLI::App* app) {
  return std::make_unique<StudyCommand>(app);
}
std::unique_ptr<Subcommand> AddTestCommand(CLI::App* app) {
  return std::make_unique<TestCommand>(app);
}

}  // namespace corridorsim::cli
