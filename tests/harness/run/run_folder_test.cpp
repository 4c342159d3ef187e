// Tests harness/run/run_folder.cpp: output folders staged and refused, results committed before the
// extras, the exit code's precedence, plots started without a shell.
#include "harness/run/run_folder.h"

#include <filesystem>
#include <stdexcept>
#include <string>

#include <catch2/catch.hpp>

#include "common/error.h"
#include "common/io/atomic_file.h"
#include "harness/run/run.h"
#include "tests/support/previous_job_folder.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;

TEST_CASE("StageOutputFolder refuses a previous run's folder naming --force", "[harness]") {
  const test::ScratchDir dir("corridorsim_stage_refuse");
  const fs::path out = dir.path() / "run";
  test::WritePreviousJobFolder(out, {{"metrics.json", "{}"}});
  try {
    StageOutputFolder(out, "--out", /*force=*/false, {});
    FAIL("a non-empty folder was accepted");
  } catch (const InputError& e) {
    CHECK(e.key() == "--out");
    CHECK_THAT(e.what(), Catch::StartsWith("command line: --out: '" + out.string()));
    CHECK_THAT(e.what(), Catch::Contains("pass --force"));
  }
  CHECK_THROWS_WITH(StageOutputFolder(out / "metrics.json" / "x", "--export", true, {}),
                    Catch::StartsWith("command line: --export: "));
  CHECK(StageOutputFolder(out, "--out", /*force=*/true, {}) != nullptr);
}

TEST_CASE("No output is, contains or lies inside an input, links resolved", "[harness]") {
  const test::ScratchDir dir("corridorsim_outputs_inputs");
  const fs::path run = dir.path() / "run";
  test::WritePreviousJobFolder(run, {{"ground_truth.tum", "1 0 0 0 0 0 0 1\n"}});
  fs::create_symlink(run, dir.path() / "link");
  const std::vector<JobInput> inputs = {{run / "ground_truth.tum", "a file of RUN_DIR"}};
  const auto message = [&](const fs::path& out) -> std::string {
    try {
      StageOutputFolder(out, "--out", /*force=*/true, inputs);
    } catch (const InputError& e) {
      CHECK(e.key() == "--out");
      return e.what();
    }
    return "";
  };
  CHECK_THAT(message(run), Catch::Contains("' contains '") && Catch::Contains("a file of RUN_DIR"));
  CHECK_THAT(message(run / "."), Catch::Contains("' contains '"));
  CHECK_THAT(message(dir.path() / "link"), Catch::Contains("' contains '"));  // through the link
  CHECK_THAT(message(dir.path() / "link" / "ground_truth.tum"), Catch::Contains("' is '"));
  CHECK_THAT(message(run / "ground_truth.tum" / "x"), Catch::Contains("' lies inside '"));
  CHECK_THAT(message(run / ".." / "run" / ""), Catch::Contains("' contains '"));
  // Beside the input, or a folder whose name only starts like it: allowed.
  CHECK(message(run / "evaluation").empty());
  CHECK(message(dir.path() / "run2").empty());
  CHECK(fs::exists(run / "ground_truth.tum"));  // refused: nothing removed
  CHECK(PathWithin(dir.path() / "link" / "x", run));
  CHECK_FALSE(PathWithin(dir.path() / "run2", run));
}

TEST_CASE("A failing map write keeps the committed results and exits 4", "[harness]") {
  const test::ScratchDir dir("corridorsim_extras_maps");
  const fs::path out = dir.path() / "run";
  StagedDirectory folder(out, false);
  bool plots_ran = false;
  const auto write_results = [](const fs::path& where) {
    WriteFileAtomic(where / "metrics.json", "{}\n");
    WriteFileAtomic(where / "maps", "a file where the maps folder goes");
  };
  const std::vector<RunExtra> extras = {
      {"maps/",
       [&] {
         // A real failure: the maps folder cannot be created under a regular file.
         EnsureWritableDirectory(folder.path() / "maps" / "odometry");
       }},
      {"plots/", [&] { plots_ran = true; }}};
  const int failed = CommitResultsThenExtras(folder, write_results, extras);
  CHECK(failed == 1);
  CHECK(plots_ran);  // one extra's failure costs only itself
  CHECK(folder.committed());
  CHECK(test::FileBytes(out / "metrics.json") == "{}\n");
  CHECK(RunExitCode(/*all_expectations_passed=*/true, failed) == kExitExtraFailed);
  CHECK(RunExitCode(/*all_expectations_passed=*/false, failed) == kExitExpectationsFailed);
  CHECK(RunExitCode(true, 0) == 0);
  CHECK(RunExitCode(false, 0) == kExitExpectationsFailed);
}

TEST_CASE("Results that fail to write leave the previous folder as it was", "[harness]") {
  const test::ScratchDir dir("corridorsim_extras_results");
  const fs::path out = dir.path() / "run";
  test::WritePreviousJobFolder(out, {{"metrics.json", "previous"}});
  bool extra_ran = false;
  {
    StagedDirectory folder(out, true);
    const auto write_results = [](const fs::path& where) {
      WriteFileAtomic(where / "metrics.json", "new");
      throw std::runtime_error("disk full");
    };
    CHECK_THROWS_WITH(
        CommitResultsThenExtras(folder, write_results, {{"plots/", [&] { extra_ran = true; }}}),
        "disk full");
  }
  CHECK_FALSE(extra_ran);
  CHECK(test::FileBytes(out / "metrics.json") == "previous");
}

}  // namespace
}  // namespace corridorsim
