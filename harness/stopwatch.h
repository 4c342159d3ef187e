#pragma once
// Wall-clock stage timing of the jobs (timing.json and the closing lines only: never part of an
// output that must be deterministic).

#include <chrono>

namespace corridorsim {

using WallClock = std::chrono::steady_clock;

/// Wall seconds from `start` to now.
inline double SecondsSince(WallClock::time_point start) {
  return std::chrono::duration<double>(WallClock::now() - start).count();
}

}  // namespace corridorsim
