#pragma once
// The job's side of the channel to the process that supervises it (harness/cli/supervisor.h):
// one pipe, written record by record (NUL-terminated), that says which staging folders exist (so
// that they are removed whatever ends the job: a signal, SIGKILL, a plugin's exit()) and that the
// job finished (its exit code, written after every result). Without a supervisor (unit tests, other
// programs) every call does nothing.

#include <filesystem>

namespace corridorsim {

/// From now on this process reports to the supervisor through `fd` (close-on-exec, never closed
/// here). Called once, before any thread exists.
void SetSupervisorChannel(int fd);

/// A staging folder is about to be created at `path` (called before it is): the supervisor
/// removes it should the job end before it is committed or removed.
void ReportStagingFolder(const std::filesystem::path& path);
/// The staging folder at `path` was committed (moved into its place) or removed.
void ReportStagingFolderGone(const std::filesystem::path& path);

/// The job finished: its results are written and `exit_code` is what the process returns. The
/// last thing main() does; a job that ends without it did not finish its work.
void ReportJobFinished(int exit_code);

}  // namespace corridorsim
