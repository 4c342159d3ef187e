#pragma once
// Wall-clock stage timing of the jobs (timing.json and the closing lines only: never part of an
// output that must be deterministic).

#include <chrono>
#include <ctime>

namespace corridorsim {

using WallClock = std::chrono::steady_clock;

/// Wall seconds from `start` to now.
inline double SecondsSince(WallClock::time_point start) {
  return std::chrono::duration<double>(WallClock::now() - start).count();
}

/// CPU seconds the calling thread has used (POSIX CLOCK_THREAD_CPUTIME_ID): a stage's own cost
/// whatever else shares the cores; 0 where the clock is not available.
inline double ThreadCpuSeconds() {
  timespec ts{};
  if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0) return 0.0;
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

}  // namespace corridorsim
