#include "common/io/child_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <linux/close_range.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <thread>

namespace corridorsim {
namespace {

constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP};
constexpr std::size_t kStopSignalCount = sizeof kStopSignals / sizeof kStopSignals[0];
volatile std::sig_atomic_t g_stop_signal = 0;
bool g_catching[kStopSignalCount] = {};  // written by CatchStopSignals only, read after fork()

extern "C" void OnStopSignal(int signal) {
  if (g_stop_signal == 0) g_stop_signal = signal;
}

// The environment of a child: this process's, with `overrides` set (replacing a variable of
// the same name).
std::vector<std::string> ChildEnvironment(
    const std::vector<std::pair<std::string, std::string>>& overrides) {
  std::vector<std::string> env;
  for (char** e = environ; e && *e; ++e) {
    const std::string entry = *e;
    const std::string name = entry.substr(0, entry.find('='));
    bool replaced = false;
    for (const auto& [key, value] : overrides) replaced = replaced || key == name;
    if (!replaced) env.push_back(entry);
  }
  for (const auto& [key, value] : overrides) env.push_back(key + "=" + value);
  return env;
}

// Starts `argv` with stdin from /dev/null and stdout and stderr to `options.output_fd` (-1: this
// process's), the descriptors of `options.pass_fds` at 3, 4, ...; returns its pid, or -1 with
// *error. The child is killed when the calling thread ends (PR_SET_PDEATHSIG), gets the default
// action of the stop signals this process catches, and reports a failed exec through a
// close-on-exec pipe.
pid_t Spawn(const std::vector<std::string>& argv, const ChildOptions& options, std::string* error) {
  const std::string program = ResolveProgram(argv[0], error);
  if (program.empty()) return -1;
  const int out_fd = options.output_fd;
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  // Built before fork(): the child may only make async-signal-safe calls.
  const bool set_env = !options.environment.empty();
  const std::vector<std::string> env_strings =
      set_env ? ChildEnvironment(options.environment) : std::vector<std::string>{};
  std::vector<char*> envp;
  for (const std::string& e : env_strings) envp.push_back(const_cast<char*>(e.c_str()));
  envp.push_back(nullptr);
  const int first_free_fd = 3 + static_cast<int>(options.pass_fds.size());
  const int in_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (in_fd < 0) {
    *error = std::string("/dev/null: ") + std::strerror(errno);
    return -1;
  }
  int report[2];
  if (::pipe2(report, O_CLOEXEC) != 0) {
    *error = std::strerror(errno);
    ::close(in_fd);
    return -1;
  }
  // A passed descriptor is first moved above every descriptor in play, so that placing one
  // never overwrites another not yet placed.
  int high_fd_base = std::max({first_free_fd, in_fd, out_fd, report[0], report[1]});
  for (const int fd : options.pass_fds) high_fd_base = std::max(high_fd_base, fd);
  ++high_fd_base;
  std::fflush(nullptr);  // what this process printed comes before the child's output
  // Every signal blocked across fork(): none reaches the child before it has reset the
  // handlers it inherits (a forwarded SIGINT would otherwise only set this process's flag in it).
  sigset_t all, old;
  sigfillset(&all);
  ::pthread_sigmask(SIG_SETMASK, &all, &old);
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid == 0) {
    // The child: async-signal-safe calls only, until exec.
    for (std::size_t i = 0; i < kStopSignalCount; ++i) {
      if (!g_catching[i]) continue;
      struct sigaction action {};
      action.sa_handler = SIG_DFL;
      ::sigemptyset(&action.sa_mask);
      ::sigaction(kStopSignals[i], &action, nullptr);
    }
    int e = 0;
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0) e = errno;
    // The parent may have ended before prctl(): then nobody waits for this child.
    if (e == 0 && ::getppid() != parent) ::_exit(127);
    const auto place = [&e](int fd, int target) {
      if (e != 0) return;
      if (fd == target) {
        if (::fcntl(target, F_SETFD, 0) != 0) e = errno;  // keep it open across exec
      } else if (::dup2(fd, target) < 0) {
        e = errno;
      }
    };
    if (options.own_process_group && e == 0 && ::setpgid(0, 0) != 0) e = errno;
    std::vector<int>::size_type n = options.pass_fds.size();
    for (std::vector<int>::size_type i = 0; i < n && e == 0; ++i) {
      if (::dup3(options.pass_fds[i], high_fd_base + static_cast<int>(i), O_CLOEXEC) < 0) e = errno;
    }
    place(in_fd, STDIN_FILENO);
    if (out_fd >= 0) {
      place(out_fd, STDOUT_FILENO);
      place(out_fd, STDERR_FILENO);
    }
    for (std::vector<int>::size_type i = 0; i < n; ++i) {
      place(high_fd_base + static_cast<int>(i), 3 + static_cast<int>(i));
    }
    // Nothing else is inherited: every other descriptor closes at exec.
    if (options.close_other_fds && e == 0 &&
        ::close_range(static_cast<unsigned>(first_free_fd), ~0U, CLOSE_RANGE_CLOEXEC) != 0) {
      e = errno;
    }
    if (e == 0 && !options.working_dir.empty() && ::chdir(options.working_dir.c_str()) != 0) {
      e = errno;
    }
    if (e == 0) {
      ::sigprocmask(SIG_SETMASK, &old, nullptr);
      if (set_env) {
        ::execve(program.c_str(), args.data(), envp.data());
      } else {
        ::execv(program.c_str(), args.data());
      }
      e = errno;
    }
    ssize_t ignored = ::write(report[1], &e, sizeof e);
    (void)ignored;
    ::_exit(127);
  }
  const int fork_errno = errno;
  ::pthread_sigmask(SIG_SETMASK, &old, nullptr);
  ::close(report[1]);
  ::close(in_fd);
  if (pid < 0) {
    ::close(report[0]);
    *error = std::strerror(fork_errno);
    return -1;
  }
  int child_errno = 0;
  ssize_t got = 0;
  while ((got = ::read(report[0], &child_errno, sizeof child_errno)) < 0 && errno == EINTR) {
  }
  ::close(report[0]);
  if (got > 0) {  // exec failed: reap the child
    int wstatus = 0;
    while (::waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {
    }
    *error = std::strerror(child_errno);
    return -1;
  }
  return pid;
}

}  // namespace

// argv[0] as a path to exec: itself when it holds a '/', else the first executable file of that
// name on PATH (as posix_spawnp and execvp search it). Empty, with *error, when there is none.
std::string ResolveProgram(const std::string& name, std::string* error) {
  if (name.find('/') != std::string::npos) return name;
  const char* path = std::getenv("PATH");
  const std::string dirs = path && *path ? path : "/bin:/usr/bin";
  int why = ENOENT;
  for (std::size_t start = 0;;) {
    const std::size_t colon = dirs.find(':', start);
    std::string dir = dirs.substr(start, colon == std::string::npos ? colon : colon - start);
    if (dir.empty()) dir = ".";
    const std::string candidate = dir + "/" + name;
    struct stat info {};
    if (::stat(candidate.c_str(), &info) == 0 && S_ISREG(info.st_mode)) {
      if (::access(candidate.c_str(), X_OK) == 0) return candidate;
      why = EACCES;
    }
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  *error = std::strerror(why);
  return "";
}

ChildStatus RunChildProcess(const std::vector<std::string>& argv) {
  if (argv.empty()) throw std::invalid_argument("RunChildProcess: no program");
  ChildProcess child(argv, "");
  return child.Wait();
}

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const ChildOptions& options) {
  ChildStatus failed;
  if (argv.empty()) {
    failed.error = "no program";
    done_ = failed;
    return;
  }
  own_group_ = options.own_process_group;
  const pid_t pid = Spawn(argv, options, &failed.error);
  if (pid < 0) {
    done_ = failed;
    return;
  }
  pid_ = pid;
}

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& log_file) {
  ChildStatus failed;
  if (argv.empty()) {
    failed.error = "no program";
    done_ = failed;
    return;
  }
  int out_fd = -1;
  if (!log_file.empty()) {
    out_fd = ::open(log_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (out_fd < 0) {
      failed.error = std::strerror(errno);
      done_ = failed;
      return;
    }
  }
  ChildOptions options;
  options.output_fd = out_fd;
  const pid_t pid = Spawn(argv, options, &failed.error);
  if (out_fd >= 0) ::close(out_fd);
  if (pid < 0) {
    done_ = failed;
    return;
  }
  pid_ = pid;
}

ChildProcess::~ChildProcess() {
  if (own_group_ && pid_ >= 0) ::kill(-pid_, SIGKILL);  // what it started too
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
    const auto seconds = [](const timeval& t) {
      return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
    };
    cpu_seconds_ = seconds(usage.ru_utime) + seconds(usage.ru_stime);
  }
  done_ = status;
  return done_;
}

ChildStatus ChildProcess::Wait() {
  while (true) {
    if (const std::optional<ChildStatus> status = Poll()) return *status;
    if (const int signal = StopSignal(); signal != 0 && !forwarded_) Signal(signal);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

void ChildProcess::Kill() {
  if (!done_ && pid_ >= 0) ::kill(pid_, SIGKILL);
}

void ChildProcess::KillGroup() {
  // The group outlives its leader while a member lives: its id stays reserved until then, so
  // this never reaches an unrelated group.
  if (own_group_ && pid_ >= 0) ::kill(-pid_, SIGKILL);
  Kill();
}

void ChildProcess::Signal(int signal) {
  if (!done_ && pid_ >= 0) ::kill(pid_, signal);
  forwarded_ = true;
}

void CatchStopSignals() {
  for (std::size_t i = 0; i < kStopSignalCount; ++i) {
    if (g_catching[i]) continue;
    struct sigaction old {};
    if (::sigaction(kStopSignals[i], nullptr, &old) != 0 || old.sa_handler == SIG_IGN) continue;
    struct sigaction action {};
    action.sa_handler = OnStopSignal;
    ::sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    if (::sigaction(kStopSignals[i], &action, nullptr) == 0) g_catching[i] = true;
  }
}

int StopSignal() { return g_stop_signal; }

void DieOfSignal(int signal) {
  std::fflush(nullptr);
  struct sigaction action {};
  action.sa_handler = SIG_DFL;
  ::sigemptyset(&action.sa_mask);
  ::sigaction(signal, &action, nullptr);
  sigset_t set;
  ::sigemptyset(&set);
  ::sigaddset(&set, signal);
  ::pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  ::raise(signal);
  ::_exit(128 + signal);
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
