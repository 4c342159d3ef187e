#include "harness/cli/supervisor.h"

#include <dirent.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/signalfd.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "common/io/child_process.h"
#include "common/io/supervisor_channel.h"

namespace corridorsim {
namespace {

using Clock = std::chrono::steady_clock;

constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP};
// Descendants left when the job ends get SIGTERM, and SIGKILL this long after (a corridorsim run
// among them, a study's, removes its staging folders meanwhile).
constexpr int kTermSeconds = 2;
// How long the reaper waits for SIGKILLed descendants to end (one in uninterruptible sleep on a
// dead NFS server may never end: it is named and left).
constexpr int kReapSeconds = 10;
// A channel record longer than this is not one the job wrote (a path is at most PATH_MAX).
constexpr std::size_t kMaxRecordBytes = 64 * 1024;

volatile sig_atomic_t g_reaper_pid = 0;  // in the top process: where stop signals go

extern "C" void ForwardToReaper(int signal) {
  const pid_t pid = g_reaper_pid;
  if (pid > 0) ::kill(pid, signal);
}

[[noreturn]] void Fail(const char* what) {
  std::fprintf(stderr, "corridorsim: error: cannot supervise the job: %s: %s\n", what,
               std::strerror(errno));
  ::_exit(1);
}

// Ends this process (top or reaper) as `signal` ends a process, without a second core file (the
// job's is the one that tells).
[[noreturn]] void DieOf(int signal) {
  const struct rlimit no_core { 0, 0 };
  ::setrlimit(RLIMIT_CORE, &no_core);
  DieOfSignal(signal);
}

// Ends this process as `wstatus` says the process below ended: its exit code, or its signal.
[[noreturn]] void EndAs(int wstatus) {
  if (WIFSIGNALED(wstatus)) DieOf(WTERMSIG(wstatus));
  ::_exit(WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : 1);
}

// The processes whose parent is `parent`, from /proc/<pid>/stat (field 4, after the command
// name, which may hold spaces and parentheses: read after the last ')').
std::vector<pid_t> ChildrenOf(pid_t parent) {
  std::vector<pid_t> children;
  DIR* proc = ::opendir("/proc");
  if (!proc) return children;
  while (const dirent* entry = ::readdir(proc)) {
    char* end = nullptr;
    const long pid = std::strtol(entry->d_name, &end, 10);
    if (pid <= 0 || *end != '\0') continue;
    char path[64];
    std::snprintf(path, sizeof path, "/proc/%ld/stat", pid);
    const int fd = ::open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) continue;
    char stat[1024];
    const ssize_t n = ::read(fd, stat, sizeof stat - 1);
    ::close(fd);
    if (n <= 0) continue;
    stat[n] = '\0';
    const char* paren = std::strrchr(stat, ')');
    int ppid = 0;
    char state = 0;
    if (paren && std::sscanf(paren + 1, " %c %d", &state, &ppid) == 2 && ppid == parent) {
      children.push_back(static_cast<pid_t>(pid));
    }
  }
  ::closedir(proc);
  return children;
}

// The reaper's state: the job, what it reported, the stop signal it was sent.
class Reaper {
 public:
  Reaper(pid_t job, int channel, int parent_pipe, int signals)
      : job_(job), channel_(channel), parent_pipe_(parent_pipe), signals_(signals) {}

  [[noreturn]] void Run();

 private:
  void ReadChannel();
  void ReadSignals();
  void ReapChildren();
  void EndAllDescendants();
  void RemoveStagingFolders();

  pid_t job_;
  int channel_;      // the job's reports; -1 once at EOF
  int parent_pipe_;  // EOF: the top process died; -1 then
  int signals_;      // signalfd: SIGCHLD and the stop signals
  std::string pending_;
  std::optional<int> reported_;
  std::set<std::string> staging_;
  int stop_signal_ = 0;
  Clock::time_point stop_deadline_;
  bool killed_after_grace_ = false;
  bool parent_gone_ = false;
  std::optional<int> job_status_;
};

void Reaper::ReadChannel() {
  char buffer[4096];
  while (channel_ >= 0) {
    const ssize_t n = ::read(channel_, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return;  // EAGAIN: nothing more now
    if (n == 0) {
      ::close(channel_);
      channel_ = -1;
      return;
    }
    pending_.append(buffer, static_cast<std::size_t>(n));
    std::size_t start = 0;
    for (std::size_t nul; (nul = pending_.find('\0', start)) != std::string::npos;
         start = nul + 1) {
      const std::string record = pending_.substr(start, nul - start);
      if (record.empty()) continue;
      const std::string text = record.substr(1);
      if (record[0] == '+') staging_.insert(text);
      if (record[0] == '-') staging_.erase(text);
      if (record[0] == '=') reported_ = std::atoi(text.c_str());
    }
    pending_.erase(0, start);
    if (pending_.size() > kMaxRecordBytes) pending_.clear();
  }
}

void Reaper::ReadSignals() {
  signalfd_siginfo info;
  while (::read(signals_, &info, sizeof info) == static_cast<ssize_t>(sizeof info)) {
    const int signal = static_cast<int>(info.ssi_signo);
    if (signal == SIGCHLD || stop_signal_ != 0) continue;
    // The first stop signal goes to the job (the same signal from a terminal reaches it too:
    // a job catches it once), and starts its grace period.
    stop_signal_ = signal;
    stop_deadline_ = Clock::now() + std::chrono::seconds(kStopGraceSeconds);
    if (!job_status_) ::kill(job_, signal);
  }
}

// Reaps every child that ended: the job, and orphans reparented here.
void Reaper::ReapChildren() {
  int wstatus = 0;
  pid_t pid;
  while ((pid = ::waitpid(-1, &wstatus, WNOHANG)) > 0) {
    if (pid == job_) job_status_ = wstatus;
  }
}

void Reaper::EndAllDescendants() {
  const Clock::time_point kill_from = Clock::now() + std::chrono::seconds(kTermSeconds);
  const Clock::time_point give_up = kill_from + std::chrono::seconds(kReapSeconds);
  std::set<pid_t> termed;
  for (;;) {
    int wstatus = 0;
    pid_t pid;
    while ((pid = ::waitpid(-1, &wstatus, WNOHANG)) > 0) {
    }
    if (pid < 0 && errno == ECHILD) return;  // none left
    // A process's own children are reparented here as it ends: the next round finds them.
    const std::vector<pid_t> children = ChildrenOf(::getpid());
    const bool hard = Clock::now() >= kill_from;
    for (const pid_t child : children) {
      if (hard) {
        ::kill(child, SIGKILL);
      } else if (termed.insert(child).second) {
        ::kill(child, SIGTERM);
        ::kill(child, SIGCONT);  // a stopped process acts on it too
      }
    }
    if (Clock::now() > give_up) {
      std::fprintf(stderr,
                   "corridorsim: warning: %zu process(es) the job started did not end within %d s "
                   "of SIGKILL (the first: pid %d)\n",
                   children.size(), kReapSeconds, children.empty() ? 0 : children.front());
      return;
    }
    pollfd fd{signals_, POLLIN, 0};
    ::poll(&fd, 1, 10);
    signalfd_siginfo info;
    while (::read(signals_, &info, sizeof info) == static_cast<ssize_t>(sizeof info)) {
    }
  }
}

// The staging folders the job reported and did not commit or remove: only names a staging
// folder of this job has (`.<name>.partial-<job pid>`), whatever the channel said.
void Reaper::RemoveStagingFolders() {
  const std::string suffix = ".partial-" + std::to_string(job_);
  for (const std::string& path : staging_) {
    const std::string name = std::filesystem::path(path).filename().string();
    if (name.size() <= suffix.size() + 1 || name[0] != '.' ||
        name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
      continue;
    }
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
}

void Reaper::Run() {
  while (!job_status_) {
    pollfd fds[3] = {{signals_, POLLIN, 0}, {channel_, POLLIN, 0}, {parent_pipe_, POLLIN, 0}};
    int timeout_ms = -1;
    if (stop_signal_ != 0 && !killed_after_grace_) {
      const auto left =
          std::chrono::duration_cast<std::chrono::milliseconds>(stop_deadline_ - Clock::now());
      timeout_ms = static_cast<int>(std::max<long long>(0, left.count()) + 1);
    }
    if (::poll(fds, 3, timeout_ms) < 0 && errno != EINTR) Fail("poll");
    ReadChannel();
    ReadSignals();
    if (parent_pipe_ >= 0 && (fds[2].revents & (POLLIN | POLLHUP | POLLERR))) {
      // The top process died (SIGKILL: nothing else ends it first): so does the job, now.
      ::close(parent_pipe_);
      parent_pipe_ = -1;
      parent_gone_ = true;
      ::kill(job_, SIGKILL);
    }
    if (stop_signal_ != 0 && !killed_after_grace_ && Clock::now() >= stop_deadline_) {
      killed_after_grace_ = true;
      ::kill(job_, SIGKILL);
    }
    ReapChildren();
  }
  ReadChannel();  // what it wrote before it ended is in the pipe whoever else holds it open
  EndAllDescendants();
  RemoveStagingFolders();
  if (parent_gone_) ::_exit(1);  // nobody waits for this process
  const int wstatus = *job_status_;
  if (stop_signal_ != 0 && (killed_after_grace_ || WIFSIGNALED(wstatus))) {
    if (killed_after_grace_) {
      std::fprintf(stderr,
                   "corridorsim: error: the job did not end within %d s of signal %d (%s); "
                   "it was killed\n",
                   kStopGraceSeconds, stop_signal_, ::strsignal(stop_signal_));
    }
    DieOf(stop_signal_);  // as the stop signal ends a process (128 + it)
  }
  if (WIFSIGNALED(wstatus)) EndAs(wstatus);
  const int code = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : 1;
  if (!reported_) {
    std::fprintf(stderr,
                 "corridorsim: error: the job ended before it finished: it exited %d without "
                 "completing (did a plugin or a library call exit()?); its staging folders are "
                 "removed and no result of it is complete\n",
                 code);
    ::_exit(code != 0 ? code : 1);
  }
  // A code changed after the report (a sanitizer's exit hook) is kept when it is a failure.
  ::_exit(code != 0 ? code : *reported_);
}

// The reaper's own start: returns in the job process only.
void StartReaper(int parent_pipe, const sigset_t& job_mask) {
  if (::prctl(PR_SET_CHILD_SUBREAPER, 1) != 0) Fail("PR_SET_CHILD_SUBREAPER");
  sigset_t handled;
  ::sigemptyset(&handled);
  ::sigaddset(&handled, SIGCHLD);
  for (const int signal : kStopSignals) ::sigaddset(&handled, signal);
  const int signals = ::signalfd(-1, &handled, SFD_CLOEXEC | SFD_NONBLOCK);
  if (signals < 0) Fail("signalfd");
  int channel[2];
  if (::pipe2(channel, O_CLOEXEC) != 0) Fail("pipe");
  const pid_t reaper = ::getpid();
  const pid_t job = ::fork();
  if (job < 0) Fail("fork");
  if (job == 0) {
    ::close(channel[0]);
    ::close(signals);
    ::close(parent_pipe);
    // The reaper ends only after the job, unless something kills it: then so is the job.
    if (::prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || ::getppid() != reaper) ::_exit(1);
    ::sigprocmask(SIG_SETMASK, &job_mask, nullptr);
    SetSupervisorChannel(channel[1]);
    return;
  }
  ::close(channel[1]);
  ::fcntl(channel[0], F_SETFL, ::fcntl(channel[0], F_GETFL) | O_NONBLOCK);
  Reaper(job, channel[0], parent_pipe, signals).Run();
}

}  // namespace

void SuperviseThisJob() {
  // Blocked from here: in the top process until its forwarding is set up, in the reaper for
  // good (it reads them from a signalfd), in the job until it starts.
  sigset_t blocked, job_mask;
  ::sigemptyset(&blocked);
  ::sigaddset(&blocked, SIGCHLD);
  for (const int signal : kStopSignals) ::sigaddset(&blocked, signal);
  ::sigprocmask(SIG_BLOCK, &blocked, &job_mask);
  int parent_pipe[2];  // only the top process holds the write end: EOF when it dies
  if (::pipe2(parent_pipe, O_CLOEXEC) != 0) Fail("pipe");
  std::fflush(nullptr);
  const pid_t reaper = ::fork();
  if (reaper < 0) Fail("fork");
  if (reaper == 0) {
    ::close(parent_pipe[1]);
    StartReaper(parent_pipe[0], job_mask);
    return;
  }
  ::close(parent_pipe[0]);
  g_reaper_pid = reaper;
  for (const int signal : kStopSignals) {
    struct sigaction current {};
    if (::sigaction(signal, nullptr, &current) != 0 || current.sa_handler == SIG_IGN) continue;
    struct sigaction forward {};
    forward.sa_handler = ForwardToReaper;
    ::sigemptyset(&forward.sa_mask);
    forward.sa_flags = SA_RESTART;
    ::sigaction(signal, &forward, nullptr);
  }
  ::sigprocmask(SIG_SETMASK, &job_mask, nullptr);
  int wstatus = 0;
  while (::waitpid(reaper, &wstatus, 0) < 0) {
    if (errno != EINTR) Fail("waitpid");
  }
  EndAs(wstatus);
}

int FinishJob(int exit_code) {
  std::fflush(stdout);
  std::fflush(stderr);
  ReportJobFinished(exit_code);
  return exit_code;
}

}  // namespace corridorsim
