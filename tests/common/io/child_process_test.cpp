// Tests common/io/child_process.cpp.
#include "common/io/child_process.h"

#include <csignal>
#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

#include "tests/support/scratch_dir.h"

namespace corridorsim {
namespace {

namespace fs = std::filesystem;

TEST_CASE("RunChildProcess passes each argument as it is, never through a shell", "[common]") {
  const test::ScratchDir dir("corridorsim_child_argv");
  // Were this pasted into a shell command, the quote would end the argument and run the rest
  // (a `touch` of ./injected_by_shell and of "$(id)").
  const std::string name = "q'; touch injected_by_shell; echo '$(id) `id` \"x\" \\";
  const ChildStatus status = RunChildProcess({"touch", (dir.path() / name).string()});
  CHECK(status.succeeded());
  CHECK(fs::exists(dir.path() / name));
  CHECK_FALSE(fs::exists("injected_by_shell"));
}

TEST_CASE("RunChildProcess reports exit codes, signals and programs that are not there",
          "[common]") {
  const ChildStatus ok = RunChildProcess({"true"});
  CHECK(ok.succeeded());
  CHECK(ok.exit_code == 0);

  const ChildStatus failed = RunChildProcess({"sh", "-c", "exit 3"});
  CHECK(failed.started);
  CHECK_FALSE(failed.succeeded());
  CHECK(failed.exit_code == 3);
  CHECK(DescribeChildStatus(failed) == "exited 3");

  const ChildStatus killed = RunChildProcess({"sh", "-c", "kill -9 $$"});
  CHECK_FALSE(killed.succeeded());
  CHECK(killed.signal == SIGKILL);
  CHECK_THAT(DescribeChildStatus(killed), Catch::StartsWith("was killed by signal 9"));

  const ChildStatus missing = RunChildProcess({"corridorsim-no-such-program"});
  CHECK_FALSE(missing.started);
  CHECK_FALSE(missing.succeeded());
  CHECK_THAT(DescribeChildStatus(missing), Catch::Contains("No such file"));
}

TEST_CASE("RunChildProcess gives the child /dev/null as stdin", "[common]") {
  // A child that reads stdin must never wait for a terminal or eat this process's input.
  const test::ScratchDir dir("corridorsim_child_stdin");
  const fs::path where = dir.path() / "stdin";
  const ChildStatus status =
      RunChildProcess({"sh", "-c", "readlink /proc/self/fd/0 > \"$1\"", "sh", where.string()});
  CHECK(status.succeeded());
  CHECK(test::FileBytes(where) == "/dev/null\n");
}

}  // namespace
}  // namespace corridorsim
