// Tests common/io/child_process.cpp.
#include "common/io/child_process.h"

#include <chrono>
#include <csignal>
#include <filesystem>
#include <memory>
#include <string>
#include <thread>

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

TEST_CASE("a child ends with the thread that started it, however that ends", "[common]") {
  // PR_SET_PDEATHSIG: a job killed with SIGKILL cannot stop its children itself; they are killed
  // by the kernel when it ends. Here the starting thread ends and leaves the child behind.
  std::unique_ptr<ChildProcess> child;
  const auto start = std::chrono::steady_clock::now();
  std::thread([&] {
    child = std::make_unique<ChildProcess>(std::vector<std::string>{"sleep", "20"}, "");
  }).join();
  REQUIRE(child->pid() > 0);
  const ChildStatus status = child->Wait();
  CHECK(status.signal == SIGKILL);
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(10));
}

TEST_CASE("a signal sent to a child ends it; Wait reaps it", "[common]") {
  ChildProcess child({"sleep", "20"}, "");
  REQUIRE(child.pid() > 0);
  child.Signal(SIGTERM);
  const ChildStatus status = child.Wait();
  CHECK(status.signal == SIGTERM);
  CHECK(child.pid() == -1);
}

TEST_CASE("a child's output goes to its log file; a program not there is reported", "[common]") {
  const test::ScratchDir dir("corridorsim_child_log");
  const fs::path log = dir.path() / "child.log";
  ChildProcess child({"sh", "-c", "echo out; echo err >&2"}, log.string());
  CHECK(child.Wait().succeeded());
  CHECK(test::FileBytes(log) == "out\nerr\n");
  ChildProcess missing({"corridorsim-no-such-program"}, log.string());
  const ChildStatus status = missing.Wait();
  CHECK_FALSE(status.started);
  CHECK_THAT(status.error, Catch::Contains("No such file"));
  ChildProcess no_log({"true"}, (dir.path() / "no" / "such" / "folder.log").string());
  CHECK_FALSE(no_log.Wait().started);
}

}  // namespace
}  // namespace corridorsim
