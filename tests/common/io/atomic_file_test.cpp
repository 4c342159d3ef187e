// Tests common/atomic_file.cpp.
#include "common/io/atomic_file.h"

#include <filesystem>
#include <stdexcept>
#include <string>

#include <catch2/catch.hpp>

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

}  // namespace
}  // namespace corridorsim
