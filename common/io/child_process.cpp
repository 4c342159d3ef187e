#include "common/io/child_process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <stdexcept>

extern char** environ;

namespace corridorsim {

ChildStatus RunChildProcess(const std::vector<std::string>& argv) {
  if (argv.empty()) throw std::invalid_argument("RunChildProcess: no program");
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);

  std::fflush(nullptr);  // what this process printed comes before the child's output
  ChildStatus status;
  posix_spawn_file_actions_t actions;
  if (int e = posix_spawn_file_actions_init(&actions); e != 0) {
    status.error = std::strerror(e);
    return status;
  }
  int e = posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  pid_t pid = -1;
  if (e == 0) e = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (e != 0) {
    status.error = std::strerror(e);
    return status;
  }
  status.started = true;
  int wstatus = 0;
  while (::waitpid(pid, &wstatus, 0) < 0) {
    if (errno != EINTR) {
      status.error = std::string("waitpid failed: ") + std::strerror(errno);
      return status;
    }
  }
  if (WIFEXITED(wstatus)) status.exit_code = WEXITSTATUS(wstatus);
  if (WIFSIGNALED(wstatus)) status.signal = WTERMSIG(wstatus);
  return status;
}

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& log_file) {
  ChildStatus failed;
  if (argv.empty()) {
    failed.error = "no program";
    done_ = failed;
    return;
  }
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  std::fflush(nullptr);
  posix_spawn_file_actions_t actions;
  if (int e = posix_spawn_file_actions_init(&actions); e != 0) {
    failed.error = std::strerror(e);
    done_ = failed;
    return;
  }
  int e = posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  if (e == 0) {
    e = posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log_file.c_str(),
                                         O_WRONLY | O_CREAT | O_TRUNC, 0644);
  }
  if (e == 0) e = posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = -1;
  if (e == 0) e = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (e != 0) {
    failed.error = std::strerror(e);
    done_ = failed;
    return;
  }
  pid_ = pid;
}

ChildProcess::~ChildProcess() {
  if (done_ || pid_ < 0) return;
  ::kill(pid_, SIGKILL);
  int wstatus = 0;
  while (::waitpid(pid_, &wstatus, 0) < 0 && errno == EINTR) {
  }
}

std::optional<ChildStatus> ChildProcess::Poll() {
  if (done_ || pid_ < 0) return done_;
  int wstatus = 0;
  struct rusage usage {};
  const pid_t got = ::wait4(pid_, &wstatus, WNOHANG, &usage);
  if (got == 0) return std::nullopt;  // still running
  ChildStatus status;
  status.started = true;
  if (got < 0) {
    if (errno == EINTR) return std::nullopt;
    status.error = std::string("wait4 failed: ") + std::strerror(errno);
  } else {
    if (WIFEXITED(wstatus)) status.exit_code = WEXITSTATUS(wstatus);
    if (WIFSIGNALED(wstatus)) status.signal = WTERMSIG(wstatus);
    peak_rss_mib_ = static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux: KiB
  }
  done_ = status;
  return done_;
}

void ChildProcess::Kill() {
  if (!done_ && pid_ >= 0) ::kill(pid_, SIGKILL);
}

std::string ThisProgram() {
  if (::access("/proc/self/exe", X_OK) != 0) {
    throw std::runtime_error("cannot find this program (/proc/self/exe)");
  }
  return "/proc/self/exe";
}

std::string DescribeChildStatus(const ChildStatus& status) {
  if (!status.started) return "could not be started: " + status.error;
  if (!status.error.empty()) return status.error;
  if (status.signal != 0) {
    return "was killed by signal " + std::to_string(status.signal) + " (" +
           ::strsignal(status.signal) + ")";
  }
  return "exited " + std::to_string(status.exit_code);
}

}  // namespace corridorsim
