#pragma once
// corridorsim supervises its own job (docs/architecture.md, "Supervision"): three processes,
//
//   corridorsim (the top: the pid a shell, CI or a study sees)
//     └─ reaper (single-threaded; PR_SET_CHILD_SUBREAPER)
//          └─ job (parses the command line and does the work: plugins, external programs)
//
// The job reports "finished, exit code N" through a pipe as main()'s last step, after every
// result is written; a job that ends without it (a plugin's exit(0) or _Exit(0), in a static
// initializer or mid-run) never makes corridorsim exit 0. Every process the job starts, however
// it detaches itself (double fork, setpgid, setsid), is reparented to the reaper once orphaned,
// and the reaper ends all that remain (SIGTERM, SIGKILL 2 s later) when the job ends: at its end,
// when the top process dies (SIGKILL included: the reaper sees its pipe close, and SIGKILLs the
// job) and after a stop signal's grace period. The staging
// folders the job reported (common/io/supervisor_channel.h) and did not commit are removed.

namespace corridorsim {

/// Seconds a job has, after the first stop signal (SIGINT, SIGTERM, SIGHUP) is forwarded to it,
/// to end on its own before it is SIGKILLed (its descendants with it, its staging folders
/// removed); corridorsim then still ends as that signal ends a process (exit status 128 + it).
constexpr int kStopGraceSeconds = 10;

/// The first thing main() does, before any thread exists. Returns in the job process only; the
/// top and reaper processes end as the job ended (its exit code, or dying of its signal) and
/// never return. A job that could not be supervised (fork or pipe failing) is an error: one
/// message, exit 1.
void SuperviseThisJob();

/// main()'s last step in the job: flushes stdout and stderr and reports `exit_code` to the
/// supervisor. Returns `exit_code`.
int FinishJob(int exit_code);

}  // namespace corridorsim
