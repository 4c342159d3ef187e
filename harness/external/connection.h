#pragma once
// A pipeline's program and the private connection to it (docs/protocol.md, "The process"):
// started as an argument vector (never a shell) in a process group of its own, with a Unix-domain
// socket at descriptor 3 (socketpair: nothing another process can connect to), stdin from
// /dev/null, stdout and stderr into a pipe whose last kLogKeepBytes this side keeps, and no
// other descriptor. Every wait on it is bounded by a deadline; the program dies with the thread
// that started it (PR_SET_PDEATHSIG) and its group is killed when the connection closes.

#include <chrono>
#include <cstddef>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/io/child_process.h"

namespace corridorsim::external {

/// The program could not be started (not found, not executable, ...): the scenario's fault.
class StartError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The program broke the connection: exited, stopped answering, sent what the protocol forbids.
/// The text says what (and, where the program ended, how).
class ConnectionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct Received {
  nlohmann::json json;
  std::string blob;
};

class ProgramConnection {
 public:
  /// The last bytes of the program's output kept (the run folder's <pipeline>.log).
  static constexpr std::size_t kLogKeepBytes = 1u << 20;

  /// Starts `argv` (argv[0] with a '/' as it is, else searched on PATH) in `working_dir` with
  /// `environment` set over this process's. Throws StartError.
  ProgramConnection(const std::vector<std::string>& argv, const std::string& working_dir,
                    const std::vector<std::pair<std::string, std::string>>& environment);
  ~ProgramConnection();  // kills the program's group and reaps it
  ProgramConnection(const ProgramConnection&) = delete;
  ProgramConnection& operator=(const ProgramConnection&) = delete;

  /// Sends one message (header, JSON, blob), `fd` (>= 0) attached to its first byte. Throws
  /// ConnectionError when the program is gone or does not read it within `timeout`.
  void Send(const nlohmann::ordered_json& json, std::string_view blob, int fd,
            std::chrono::duration<double> timeout);
  /// Reads one message within `timeout`. Throws ConnectionError (with ProtocolError's text for a
  /// malformed one) when it does not come.
  Received Receive(std::chrono::duration<double> timeout);

  /// Ends the connection: closes this side, waits up to `grace` for the program to exit, then
  /// kills its group. Returns how it ended (nothing if it could not be reaped in time).
  std::optional<ChildStatus> Close(std::chrono::duration<double> grace);
  /// Kills the program's group now (a failed pipeline) and collects what it printed until then.
  void Kill();

  /// The program's CPU seconds (user + system, with the children it waited for) and peak memory
  /// in MiB once it was reaped (Close, Kill), else -1 each.
  double program_cpu_seconds() const { return child_->cpu_seconds(); }
  double program_peak_rss_mib() const {
    return child_->cpu_seconds() >= 0 ? child_->peak_rss_mib() : -1.0;
  }

  /// What the program printed (stdout and stderr, in order), at most the last kLogKeepBytes,
  /// headed by a line saying how much was left out.
  std::string Log() const;
  /// Its last `lines` lines, at most `max_bytes`, for a failure's reason.
  std::string LogTail(std::size_t lines, std::size_t max_bytes) const;

 private:
  // Waits until the socket is ready for `events` (POLLIN / POLLOUT) or the deadline, reading the
  // program's output meanwhile. False at the deadline.
  bool WaitFor(short events, std::chrono::steady_clock::time_point deadline);
  void DrainLog();
  void AppendLog(const char* data, std::size_t n);
  // "the program exited 3" / "... was killed by signal 11 (Segmentation fault)" / "... closed
  // the connection", after reaping it for a moment.
  std::string WhyGone(const std::string& what);

  std::unique_ptr<ChildProcess> child_;
  int socket_ = -1;
  int log_fd_ = -1;
  std::string log_;
  std::size_t log_dropped_ = 0;
  std::string program_;
};

}  // namespace corridorsim::external
