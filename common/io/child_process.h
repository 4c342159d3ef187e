#pragma once
// Starting another program without a shell: the arguments go to it as a vector, so no character
// of a path (quote, semicolon, `$(...)`, newline) is ever interpreted.
//
// A child never outlives the job that started it: it is killed (SIGKILL, prctl's
// PR_SET_PDEATHSIG) when the thread that started it ends, however that thread ends (kill -9
// included), and a job that catches stop signals (CatchStopSignals) forwards them to its
// children and waits for them before it ends.

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace corridorsim {

/// How a child process ended.
struct ChildStatus {
  bool started = false;  // false: it could not be started (`error` says why)
  int exit_code = -1;    // its exit status when it exited
  int signal = 0;        // the signal that ended it, or 0
  std::string error;     // why it could not be started (e.g. "No such file or directory")

  bool succeeded() const { return started && signal == 0 && exit_code == 0; }
};

/// Runs `argv[0]` (searched on PATH when it has no '/') with the arguments `argv` and waits for
/// it (ChildProcess::Wait): stdin reads /dev/null, stdout and stderr are this process's (flushed
/// first). Never uses a shell. `argv` must not be empty.
ChildStatus RunChildProcess(const std::vector<std::string>& argv);

/// argv[0] as a path to exec: itself when it holds a '/', else the first executable regular file
/// of that name on PATH (as posix_spawnp and execvp search it). Empty, with *error, when there
/// is none.
std::string ResolveProgram(const std::string& name, std::string* error);

/// How a ChildProcess starts, beyond its arguments.
struct ChildOptions {
  int output_fd = -1;           // its stdout and stderr; -1: this process's
  std::vector<int> pass_fds;    // placed at descriptors 3, 4, ... in the child
  bool close_other_fds = true;  // every descriptor above those closes at exec, close-on-exec or not
  std::string working_dir;      // "" : this process's
  std::vector<std::pair<std::string, std::string>> environment;  // set over this process's
  // A process group of its own (its pid): KillGroup() and the destructor end what it started too.
  bool own_process_group = false;
};

/// A child started without waiting for it (a study's worker runs). Its stdout and stderr go to
/// one log file (created or truncated; empty: this process's), stdin reads /dev/null; never a
/// shell. It is killed when the thread that started it ends (see above): start children from a
/// thread that outlives them (the main thread).
class ChildProcess {
 public:
  /// Starts `argv` (argv[0] searched on PATH when it has no '/'). On failure the object is not
  /// running and Poll() returns a status whose `error` says why.
  ChildProcess(const std::vector<std::string>& argv, const std::string& log_file);
  /// Starts `argv` as `options` say (an external pipeline's program).
  ChildProcess(const std::vector<std::string>& argv, const ChildOptions& options);
  ~ChildProcess();  // kills and reaps a child still running (SIGKILL)
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// The status once it ended (reaped then), else nothing. Never blocks.
  std::optional<ChildStatus> Poll();
  /// Waits until it ended. A stop signal this process catches meanwhile (StopSignal()) is
  /// forwarded to the child once, and the wait goes on until it has ended.
  ChildStatus Wait();
  /// SIGKILL (it is reaped by the next Poll()).
  void Kill();
  /// SIGKILL to its process group (own_process_group), else as Kill().
  void KillGroup();
  /// Sends `signal` to a child still running (a stop signal forwarded).
  void Signal(int signal);
  /// Its process id while it runs or before it is reaped, else -1.
  int pid() const { return done_ ? -1 : pid_; }
  /// Its peak resident memory in MiB once ended (from wait4's rusage), else 0.
  double peak_rss_mib() const { return peak_rss_mib_; }
  /// Its CPU time (user + system, with the children it waited for) in seconds once ended (from
  /// wait4's rusage), else -1.
  double cpu_seconds() const { return cpu_seconds_; }

 private:
  int pid_ = -1;
  bool forwarded_ = false;
  bool own_group_ = false;
  std::optional<ChildStatus> done_;
  double peak_rss_mib_ = 0.0;
  double cpu_seconds_ = -1.0;
};

/// From now on SIGINT, SIGTERM and SIGHUP, each unless this process was started with it ignored
/// (nohup, a background job of a script), do not end this process but are recorded
/// (StopSignal()), so that a job with children can stop them, wait for them and then end as the
/// signal would have ended it (DieOfSignal). Children started later get the default actions back.
void CatchStopSignals();

/// The first stop signal caught since CatchStopSignals(), or 0.
int StopSignal();

/// Ends this process as `signal` ends it by default (its default action restored and the signal
/// raised; exit 128 + signal should it survive that), stdout and stderr flushed first.
[[noreturn]] void DieOfSignal(int signal);

/// This very program as a path to start again: /proc/self/exe itself rather than the file it
/// points to, so that rebuilding the program while it runs (the linker writes a new file) cannot
/// change what its children run. Throws std::runtime_error without /proc.
std::string ThisProgram();

/// "exited 3", "was killed by signal 9 (Killed)", "could not be started: <why>".
std::string DescribeChildStatus(const ChildStatus& status);

}  // namespace corridorsim
