#include "harness/external/exchange_timing.h"

#include <algorithm>
#include <cmath>

#include "common/io/stable_json.h"

namespace corridorsim::external {
namespace {

// In the order of the exchange (docs/protocol.md); imu and scan: version 2 only.
constexpr std::array<std::string_view, kMessageKinds> kKinds = {"start", "odometry", "imu",
                                                                "scan",  "cameras",  "finish"};

// Milliseconds to 1e-4 (0.1 us), seconds to 1e-6.
double Ms(double seconds) { return RoundToStep(seconds * 1e3, 1e4); }
double Seconds(double seconds) { return RoundToStep(seconds, 1e6); }

// The q-quantile of sorted values, by linear interpolation between the nearest ranks.
double Quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const double at = q * static_cast<double>(sorted.size() - 1);
  const std::size_t lo = static_cast<std::size_t>(std::floor(at));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (at - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

}  // namespace

void ExchangeTimes::Add(std::string_view kind, double seconds) {
  for (std::size_t k = 0; k < kKinds.size(); ++k) {
    if (kKinds[k] == kind) seconds_[k].push_back(seconds);
  }
}

std::size_t ExchangeTimes::messages() const {
  std::size_t n = 0;
  for (const std::vector<double>& s : seconds_) n += s.size();
  return n;
}

double ExchangeTimes::total_seconds() const {
  double total = 0.0;
  for (const std::vector<double>& s : seconds_) {
    for (const double v : s) total += v;
  }
  return total;
}

nlohmann::ordered_json ExchangeTimes::RoundTripMsJson() const {
  nlohmann::ordered_json out = nlohmann::ordered_json::object();
  for (std::size_t k = 0; k < kKinds.size(); ++k) {
    if (seconds_[k].empty()) continue;
    std::vector<double> sorted = seconds_[k];
    std::sort(sorted.begin(), sorted.end());
    double sum = 0.0;
    for (const double v : sorted) sum += v;
    out[std::string(kKinds[k])] = {{"messages", sorted.size()},
                                   {"mean", Ms(sum / static_cast<double>(sorted.size()))},
                                   {"p50", Ms(Quantile(sorted, 0.5))},
                                   {"p90", Ms(Quantile(sorted, 0.9))},
                                   {"max", Ms(sorted.back())}};
  }
  return out;
}

nlohmann::ordered_json ProtocolTimingJson(const ExchangeTimes& times, const ProgramUsage& usage,
                                          double program_reported_seconds, bool program_reported,
                                          double corridorsim_cpu_seconds) {
  const std::size_t messages = times.messages();
  const auto per_message_ms = [messages](double seconds) {
    return messages > 0 ? nlohmann::ordered_json(Ms(seconds / static_cast<double>(messages)))
                        : nlohmann::ordered_json();
  };
  const auto known = [](double v, double rounded) {
    return v >= 0 ? nlohmann::ordered_json(rounded) : nlohmann::ordered_json();
  };
  nlohmann::ordered_json out;
  out["messages"] = messages;
  out["round_trip_seconds"] = Seconds(times.total_seconds());
  out["round_trip_ms"] = times.RoundTripMsJson();
  out["program_reported_seconds"] = program_reported
                                        ? nlohmann::ordered_json(Seconds(program_reported_seconds))
                                        : nlohmann::ordered_json();
  out["program_reported_ms_per_message"] =
      program_reported ? per_message_ms(program_reported_seconds) : nlohmann::ordered_json();
  out["program_cpu_seconds"] = known(usage.cpu_seconds, Seconds(usage.cpu_seconds));
  out["program_cpu_ms_per_message"] =
      usage.cpu_seconds >= 0 ? per_message_ms(usage.cpu_seconds) : nlohmann::ordered_json();
  out["program_peak_rss_mib"] = known(usage.peak_rss_mib, RoundToStep(usage.peak_rss_mib, 1e3));
  out["corridorsim_cpu_seconds"] = Seconds(corridorsim_cpu_seconds);
  out["corridorsim_cpu_ms_per_message"] = per_message_ms(corridorsim_cpu_seconds);
  return out;
}

}  // namespace corridorsim::external
