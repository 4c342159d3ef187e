#pragma once
// Simulation time: int64 nanoseconds, never an accumulated double.

#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace corridorsim {

/// A point in simulated time or a duration, in nanoseconds.
using TimeNs = std::int64_t;

inline constexpr TimeNs kNanosecondsPerSecond = 1'000'000'000;

/// The longest simulated run (s): the bound of `duration_s`, of a path's nominal driving time and
/// of a sensor's period. 1e6 s is 1e15 ns, far inside int64 (9.2e18 ns), so sums of a few such
/// times (a run's end with its safety margin, a phase plus a period) cannot overflow.
inline constexpr double kMaxRunSeconds = 1e6;
/// The slowest sensor rate (Hz): its period is kMaxRunSeconds.
inline constexpr double kMinSensorRateHz = 1.0 / kMaxRunSeconds;

/// Seconds as a double, for output formats (TUM files) and arithmetic in physical units.
constexpr double ToSeconds(TimeNs t) { return static_cast<double>(t) * 1e-9; }

/// Whether `seconds` converts to TimeNs without overflow: finite and within +-2^62 ns (146 years;
/// user input is bounded far below that by its option tables).
constexpr bool RepresentableSeconds(double seconds) {
  const double ns = seconds * 1e9;
  return ns > -4.6e18 && ns < 4.6e18;  // false for NaN and infinities
}

/// Nearest nanosecond of a duration given in seconds (for configuration values such as rates).
/// The value must be RepresentableSeconds (the option tables bound every time a user gives):
/// anything else is a bug and aborts rather than overflow.
constexpr TimeNs FromSeconds(double seconds) {
  if (!RepresentableSeconds(seconds)) {
    std::fprintf(stderr, "corridorsim: FromSeconds: %g s does not fit int64 nanoseconds\n",
                 seconds);
    std::abort();
  }
  const double ns = seconds * 1e9;
  return static_cast<TimeNs>(ns < 0 ? ns - 0.5 : ns + 0.5);
}

/// Period of a sensor running at `rate_hz`, rounded to the nearest nanosecond. A rate whose
/// period is not a whole number of nanoseconds runs at 1e9 / PeriodFromRateHz(rate_hz) Hz:
/// stamps are phase + n * period exactly, so they never drift from each other, and they differ
/// from n / rate_hz by at most n * 0.5 ns. rate_hz must be positive with a representable period.
constexpr TimeNs PeriodFromRateHz(double rate_hz) { return FromSeconds(1.0 / rate_hz); }

}  // namespace corridorsim
