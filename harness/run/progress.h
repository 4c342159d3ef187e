#pragma once
// A live progress line for long jobs: rewritten in place on a terminal (5 times a second), a
// plain log line at every 10 % of progress or every 10 s otherwise (CI logs, Slurm output).

#include <chrono>
#include <functional>
#include <string>

#include "common/time.h"
#include "harness/run/sensor_bus.h"

namespace corridorsim {

class Progress {
 public:
  /// `job` prefixes every line ("drive", "run").
  explicit Progress(std::string job);
  /// Simulated time, the fraction done in [0, 1] and free text appended to the line (e.g. the
  /// pipelines' current errors).
  void Update(TimeNs sim_ns, double fraction, const std::string& extra);
  /// Ends the in-place line on a terminal.
  void Finish();
  double wall_s() const;

 private:
  using Clock = std::chrono::steady_clock;
  std::string Line(TimeNs sim_ns, double fraction, const std::string& extra,
                   Clock::time_point now) const;

  std::string job_;
  bool tty_;
  Clock::time_point start_, last_;
  int last_decile_ = 0;
};

/// The live line as a bus consumer: updated every 0.1 s of simulated time and at the end, with
/// the simulation's progress and `extra()` (e.g. each pipeline's current error).
class ProgressLine : public BusConsumer {
 public:
  ProgressLine(std::string job, const sim::Simulation& simulation,
               std::function<std::string()> extra = {});
  /// The same line over another stream (a replayed recording): `fraction()` is its progress.
  ProgressLine(std::string job, std::function<double()> fraction,
               std::function<std::string()> extra = {});
  void OnStepEnd(const sim::TruthSample& truth, bool last) override;
  double wall_s() const { return progress_.wall_s(); }

 private:
  Progress progress_;
  std::function<double()> fraction_;
  std::function<std::string()> extra_;
  TimeNs period_ns_;
};

}  // namespace corridorsim
