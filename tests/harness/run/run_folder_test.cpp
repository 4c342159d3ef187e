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
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;

TEST_CASE("StageOutputFolder refuses a previous run's folder naming --force", "[harness]") {
  const test::ScratchDir dir("corridorsim_stage_refuse");
  const fs::path out = dir.path() / "run";
  fs::create_directories(out);
  WriteFileAtomic(out / StagedDirectory::kOutputFolderMarker, "");  // a previous run's folder
  WriteFileAtomic(out / "metrics.json", "{}");
  try {
    StageOutputFolder(out, "--out", /*force=*/false);
    FAIL("a non-empty folder was accepted");
  } catch (const InputError& e) {
    CHECK(e.key() == "--out");
    CHECK_THAT(e.what(), Catch::StartsWith("command line: --out: '" + out.string()));
    CHECK_THAT(e.what(), Catch::Contains("pass --force"));
  }
  CHECK_THROWS_WITH(StageOutputFolder(out / "metrics.json" / "x", "--export", true),
                    Catch::StartsWith("command line: --export: "));
  CHECK(StageOutputFolder(out, "--out", /*force=*/true) != nullptr);
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
  fs::create_directories(out);
  WriteFileAtomic(out / StagedDirectory::kOutputFolderMarker, "");
  WriteFileAtomic(out / "metrics.json", "previous");
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
