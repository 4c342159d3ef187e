// Tests common/atomic_file.cpp.
#include "common/io/atomic_file.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

namespace fs = std::filesystem;

// A fresh folder under the system temp folder, removed at the end of the test.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name)
      : path_(fs::temp_directory_path() /
              ("corridorsim_atomic_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;
    fs::permissions(path_, fs::perms::owner_all, fs::perm_options::add, ignored);
    fs::remove_all(path_, ignored);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

int CountEntries(const fs::path& dir) {
  int count = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(dir)) ++count;
  return count;
}

TEST_CASE("WriteFileAtomic replaces the content and leaves no temporary file", "[common]") {
  const ScratchDir dir("replace");
  const fs::path file = dir.path() / "out.txt";
  WriteFileAtomic(file, "first version, longer than the second\n");
  CHECK(ReadFile(file) == "first version, longer than the second\n");
  WriteFileAtomic(file, std::string_view("second\0bytes", 12));
  CHECK(ReadFile(file) == std::string("second\0bytes", 12));
  CHECK(CountEntries(dir.path()) == 1);
  WriteFileAtomic(file, "");
  CHECK(fs::file_size(file) == 0);
}

TEST_CASE("WriteFileAtomic names the file when its folder is missing", "[common]") {
  const ScratchDir dir("missing");
  const fs::path file = dir.path() / "no_such_folder" / "out.txt";
  CHECK_THROWS_WITH(WriteFileAtomic(file, "x"), Catch::Contains(file.string()));
  CHECK(CountEntries(dir.path()) == 0);
}

TEST_CASE("EnsureWritableDirectory creates nested folders and leaves no probe", "[common]") {
  const ScratchDir dir("nested");
  const fs::path nested = dir.path() / "a" / "b";
  EnsureWritableDirectory(nested);
  CHECK(fs::is_directory(nested));
  CHECK(CountEntries(nested) == 0);
  EnsureWritableDirectory(nested);  // existing and writable: fine
}

TEST_CASE("EnsureWritableDirectory throws for a folder under a regular file", "[common]") {
  const ScratchDir dir("under_file");
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
  const ScratchDir dir("read_only");
  const fs::path locked = dir.path() / "locked";
  fs::create_directories(locked);
  fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
  CHECK_THROWS_WITH(EnsureWritableDirectory(locked), Catch::Contains("not writable"));
  fs::permissions(locked, fs::perms::owner_all);
}

}  // namespace
}  // namespace corridorsim
