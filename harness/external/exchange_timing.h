#pragma once
// What an external pipeline cost, measured on both sides of the connection (timing.json's
// `pipelines.<name>.protocol`, docs/protocol.md "Cost"): the round trip of every message, from
// the moment corridorsim starts sending it to the moment the reply is read (the program's work on
// it, the two context switches and both sides' JSON), by message kind; and what the program
// itself reported and used. Wall clock: never part of a deterministic output.

#include <array>
#include <cstddef>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace corridorsim::external {

/// Message kinds timed: start, odometry, imu, scan, cameras, finish.
inline constexpr std::size_t kMessageKinds = 6;

/// The round trips of one connection by message kind (start, odometry, imu, scan, cameras,
/// finish). Every
/// round trip is kept (8 bytes a message: a run's messages are bounded by its simulated time and
/// the sensor rates) so that the percentiles are exact.
class ExchangeTimes {
 public:
  /// One exchange of `kind` (one of kMessageKinds; another is ignored).
  void Add(std::string_view kind, double seconds);
  std::size_t messages() const;
  double total_seconds() const;
  /// {"<kind>": {"messages", "mean", "p50", "p90", "max"}} in milliseconds, kinds in the order
  /// of the protocol, only those sent.
  nlohmann::ordered_json RoundTripMsJson() const;

 private:
  std::array<std::vector<double>, kMessageKinds> seconds_;
};

/// What the program itself cost, read when it was reaped (wait4's rusage: the program and the
/// children it waited for); negative: not known (it was not reaped).
struct ProgramUsage {
  double cpu_seconds = -1.0;   // user + system
  double peak_rss_mib = -1.0;  // its peak resident memory
};

/// timing.json's `protocol` section of an external pipeline: the round trips, the program's own
/// figures (`program_*`: its reported stage_seconds, its CPU time) and corridorsim's side of the
/// exchanges (`corridorsim_cpu_*`: the CPU time of corridorsim's threads during them, which is
/// what `cpu_*` measures for a pipeline inside corridorsim).
nlohmann::ordered_json ProtocolTimingJson(const ExchangeTimes& times, const ProgramUsage& usage,
                                          double program_reported_seconds, bool program_reported,
                                          double corridorsim_cpu_seconds);

}  // namespace corridorsim::external
