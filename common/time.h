#pragma once
// Simulation time: int64 nanoseconds, never an accumulated double.

#include <cstdint>

namespace corridorsim {

/// A point in simulated time or a duration, in nanoseconds.
using TimeNs = std::int64_t;

inline constexpr TimeNs kNanosecondsPerSecond = 1'000'000'000;

/// Seconds as a double, for output formats (TUM files) and arithmetic in physical units.
constexpr double ToSeconds(TimeNs t) { return static_cast<double>(t) * 1e-9; }

/// Nearest nanosecond of a duration given in seconds (for configuration values such as rates).
constexpr TimeNs FromSeconds(double seconds) {
  const double ns = seconds * 1e9;
  return static_cast<TimeNs>(ns < 0 ? ns - 0.5 : ns + 0.5);
}

/// Period of a sensor running at `rate_hz`, rounded to the nearest nanosecond.
constexpr TimeNs PeriodFromRateHz(double rate_hz) { return FromSeconds(1.0 / rate_hz); }

}  // namespace corridorsim
