// Tests common/atomic_file.cpp.
#include "common/io/atomic_file.h"

#include <unistd.h>

#include <filesystem>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>

#include <catch2/catch.hpp>

#include "tests/support/previous_job_folder.h"
#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;

using test::FileBytes;

int CountEntries(const fs::path& dir) {
  int count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++count;
  return count;
}

TEST_CASE("WriteFileAtomic replaces the content and leaves no temporary file", "[common]") {
  const test::ScratchDir dir("corridorsim_atomic_replace");
  const fs::path file = dir.path() / "out.txt";
  WriteFileAtomic(file, "first version, longer than the second\n");
  CHECK(FileBytes(file) == "first version, longer than the second\n");
  WriteFileAtomic(file, std::string_view("second\0bytes", 12));
  CHECK(FileBytes(file) == std::string("second\0bytes", 12));
  CHECK(CountEntries(dir.path()) == 1);
  WriteFileAtomic(file, "");
  CHECK(fs::file_size(file) == 0);
}

TEST_CASE("WriteFileAtomic names the file when its folder is missing", "[common]") {
  const test::ScratchDir dir("corridorsim_atomic_missing");
  const fs::path file = dir.path() / "no_such_folder" / "out.txt";
  CHECK_THROWS_WITH(WriteFileAtomic(file, "x"), Catch::Contains(file.string()));
  CHECK(CountEntries(dir.path()) == 0);
}

TEST_CASE("EnsureWritableDirectory creates nested folders and leaves no probe", "[common]") {
  const test::ScratchDir dir("corridorsim_atomic_nested");
  const fs::path nested = dir.path() / "a" / "b";
  EnsureWritableDirectory(nested);
  CHECK(fs::is_directory(nested));
  CHECK(CountEntries(nested) == 0);
  EnsureWritableDirectory(nested);  // existing and writable: fine
}

TEST_CASE("EnsureWritableDirectory throws for a folder under a regular file", "[common]") {
  const test::ScratchDir dir("corridorsim_atomic_under_file");
  const fs::path file = dir.path() / "plain_file";
  WriteFileAtomic(file, "x");
  const fs::path bad = file / "sub";
  CHECK_THROWS_AS(EnsureWritableDirectory(bad), std::runtime_error);
  CHECK_THROWS_WITH(EnsureWritableDirectory(bad), Catch::Contains(bad.string()));
  CHECK_THROWS_WITH(EnsureWritableDirectory(file), Catch::Contains(file.string()));
}

TEST_CASE("EnsureWritableDirectory throws for a read-only folder", "[common]") {
  if (::geteuid() == 0) {
    WARN("running as root, which may write anywhere: read-only check skipped");
    return;
  }
  const test::ScratchDir dir("corridorsim_atomic_read_only");
  const fs::path locked = dir.path() / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  CHECK_THROWS_WITH(EnsureWritableDirectory(locked), Catch::Contains("not writable"));
  fs::permissions(locked, fs::perms::owner_all);
}

// The names in `dir`, sorted.
std::set<std::string> Names(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename());
  return names;
}

TEST_CASE("StagedDirectory writes beside the target and commits it in one rename", "[common]") {
  const test::ScratchDir dir("corridorsim_staged_new");
  const fs::path target = dir.path() / "parent" / "run";
  StagedDirectory staged(target, /*replace_existing=*/false);
  CHECK(staged.path().parent_path() == target.parent_path());
  CHECK(staged.path().filename() == ".run.partial-" + std::to_string(::getpid()));
  WriteFileAtomic(staged.path() / "metrics.json", "{}\n");
  CHECK_FALSE(fs::exists(target));  // nothing visible before the commit
  staged.Commit();
  CHECK(staged.committed());
  CHECK(staged.path() == target);
  CHECK(FileBytes(target / "metrics.json") == "{}\n");
  CHECK(Names(target.parent_path()) == std::set<std::string>{"run"});
  CHECK_THROWS_AS(staged.Commit(), std::logic_error);
}

TEST_CASE("StagedDirectory refuses a folder with files unless told to replace it", "[common]") {
  const test::ScratchDir dir("corridorsim_staged_refuse");
  const fs::path target = dir.path() / "run";
  fs::create_directories(target);
  WriteFileAtomic(target / "old.txt", "old");
  CHECK_THROWS_AS(StagedDirectory(target, false), FolderNotEmptyError);
  CHECK(Names(dir.path()) == std::set<std::string>{"run"});  // no staging folder left
  CHECK(FileBytes(target / "old.txt") == "old");
  // An empty folder is no previous run: it is used without permission.
  fs::remove(target / "old.txt");
  StagedDirectory empty(target, false);
  WriteFileAtomic(empty.path() / "new.txt", "new");
  empty.Commit();
  CHECK(Names(target) == std::set<std::string>{StagedDirectory::kOutputFolderMarker, "new.txt"});
}

TEST_CASE("StagedDirectory replaces a previous folder whole, never a mix", "[common]") {
  const test::ScratchDir dir("corridorsim_staged_replace");
  const fs::path target = dir.path() / "run";
  test::WritePreviousJobFolder(
      target, {{"metrics.json", "old"}, {"plots/old.png", "old"}, {"only_in_old.tum", "old"}});
  {
    StagedDirectory staged(target, /*replace_existing=*/true);
    WriteFileAtomic(staged.path() / "metrics.json", "new");
    CHECK(FileBytes(target / "metrics.json") == "old");  // untouched until the commit
    staged.Commit();
  }
  CHECK(Names(target) ==
        std::set<std::string>{StagedDirectory::kOutputFolderMarker, "metrics.json"});
  CHECK(FileBytes(target / "metrics.json") == "new");
  CHECK(Names(dir.path()) == std::set<std::string>{"run"});  // the previous folder is gone
}

TEST_CASE("StagedDirectory replaces only a folder that a corridorsim job wrote", "[common]") {
  // `--force --out scenarios` (or any folder a user filled) must not delete it.
  const test::ScratchDir dir("corridorsim_staged_foreign");
  const fs::path target = dir.path() / "scenarios";
  fs::create_directories(target);
  WriteFileAtomic(target / "default.yaml", "mine");
  CHECK_THROWS_WITH(StagedDirectory(target, /*replace_existing=*/true),
                    Catch::Contains("no corridorsim job wrote") &&
                        Catch::Contains(StagedDirectory::kOutputFolderMarker));
  CHECK(Names(dir.path()) == std::set<std::string>{"scenarios"});
  CHECK(Names(target) == std::set<std::string>{"default.yaml"});
  // A folder whose marker is not a plain file is not ours either.
  fs::create_directories(target / StagedDirectory::kOutputFolderMarker);
  CHECK_THROWS(StagedDirectory(target, true));
  CHECK(FileBytes(target / "default.yaml") == "mine");
}

TEST_CASE("StagedDirectory not committed leaves the previous folder untouched", "[common]") {
  const test::ScratchDir dir("corridorsim_staged_abandon");
  const fs::path target = dir.path() / "run";
  test::WritePreviousJobFolder(target, {{"metrics.json", "old"}});
  {
    StagedDirectory staged(target, true);
    WriteFileAtomic(staged.path() / "metrics.json", "half of a new run");
  }  // the job failed: no Commit
  CHECK(Names(dir.path()) == std::set<std::string>{"run"});
  CHECK(Names(target) ==
        std::set<std::string>{StagedDirectory::kOutputFolderMarker, "metrics.json"});
  CHECK(FileBytes(target / "metrics.json") == "old");
}

TEST_CASE("StagedDirectory removes staging folders of processes that no longer run", "[common]") {
  const test::ScratchDir dir("corridorsim_staged_stale");
  const fs::path target = dir.path() / "run";
  // pid 999999999 is above any pid_max; a live process's folder (our parent's) is kept.
  const fs::path dead = dir.path() / ".run.partial-999999999";
  const fs::path dead_old = dir.path() / ".run.partial-999999998.old";
  const fs::path alive = dir.path() / (".run.partial-" + std::to_string(::getppid()));
  const fs::path other = dir.path() / ".other.partial-999999999";
  for (const fs::path& p : {dead, dead_old, alive, other}) fs::create_directories(p / "x");
  StagedDirectory staged(target, false);
  staged.Commit();
  CHECK(Names(dir.path()) ==
        std::set<std::string>{".other.partial-999999999", alive.filename().string(), "run"});
}

TEST_CASE("StagedDirectory names the folder it cannot use", "[common]") {
  const test::ScratchDir dir("corridorsim_staged_bad");
  const fs::path file = dir.path() / "plain_file";
  WriteFileAtomic(file, "x");
  CHECK_THROWS_WITH(StagedDirectory(file, true), Catch::Contains("is not a directory"));
  CHECK_THROWS_WITH(StagedDirectory(file / "run", true), Catch::Contains(file.string()));
  CHECK_THROWS_WITH(StagedDirectory(fs::current_path(), true), Catch::Contains("current folder"));
  CHECK_THROWS_WITH(StagedDirectory(fs::current_path().parent_path(), true),
                    Catch::Contains("current folder"));
  CHECK_THROWS_WITH(StagedDirectory("/", true), Catch::Contains("names no folder"));
  CHECK_THROWS_WITH(StagedDirectory("", true), Catch::Contains("empty path"));
  CHECK(Names(dir.path()) == std::set<std::string>{"plain_file"});
}

TEST_CASE("NormalOutputFolder gives one name per folder", "[common]") {
  const fs::path cwd = fs::current_path();
  CHECK(NormalOutputFolder("out/run/") == cwd / "out" / "run");
  CHECK(NormalOutputFolder("./out//run") == cwd / "out" / "run");
  CHECK(NormalOutputFolder("out/x/../run") == cwd / "out" / "run");
  CHECK(NormalOutputFolder("/tmp/a/") == fs::path("/tmp/a"));
}

}  // namespace
}  // namespace corridorsim
