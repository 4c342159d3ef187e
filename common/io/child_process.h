#pragma once
// Starting another program without a shell: the arguments go to it as a vector, so no character
// of a path (quote, semicolon, `$(...)`, newline) is ever interpreted.

#include <string>
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
/// it: stdin reads /dev/null, stdout and stderr are this process's (flushed first). Never uses a
/// shell. `argv` must not be empty.
ChildStatus RunChildProcess(const std::vector<std::string>& argv);

/// "exited 3", "was killed by signal 9 (Killed)", "could not be started: <why>".
std::string DescribeChildStatus(const ChildStatus& status);

}  // namespace corridorsim
