#include "harness/run/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <utility>

namespace corridorsim {

Progress::Progress(std::string job)
    : job_(std::move(job)),
      tty_(isatty(fileno(stdout)) != 0),
      start_(Clock::now()),
      last_(start_) {}

void Progress::Update(TimeNs sim_ns, double fraction, const std::string& extra) {
  const Clock::time_point now = Clock::now();
  if (tty_) {
    if (now - last_ < std::chrono::milliseconds(200)) return;
    // Clear to the end of the line: the previous line may have been longer.
    std::printf("\r%s\033[K", Line(sim_ns, fraction, extra, now).c_str());
  } else {
    const int decile = static_cast<int>(fraction * 10);
    if (decile <= last_decile_ && now - last_ < std::chrono::seconds(10)) return;
    last_decile_ = std::max(last_decile_, decile);
    std::printf("%s\n", Line(sim_ns, fraction, extra, now).c_str());
  }
  std::fflush(stdout);
  last_ = now;
}

void Progress::Finish() {
  if (tty_) std::printf("\n");
}

double Progress::wall_s() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

std::string Progress::Line(TimeNs sim_ns, double fraction, const std::string& extra,
                           Clock::time_point now) const {
  const double wall = std::chrono::duration<double>(now - start_).count();
  const double sim = ToSeconds(sim_ns);
  const double rtf = wall > 0 ? sim / wall : 0.0;
  const double eta = fraction > 0 ? wall * (1 - fraction) / fraction : 0.0;
  char buf[160];
  std::snprintf(buf, sizeof(buf), "%s: sim %7.1f s  %5.1f %%  real-time factor %6.1fx  ETA %4.0f s",
                job_.c_str(), sim, 100 * fraction, rtf, eta);
  return extra.empty() ? std::string(buf) : std::string(buf) + "  " + extra;
}

ProgressLine::ProgressLine(std::string job, const sim::Simulation& simulation,
                           std::function<std::string()> extra)
    : ProgressLine(
          std::move(job), [&simulation] { return simulation.progress(); }, std::move(extra)) {}

ProgressLine::ProgressLine(std::string job, std::function<double()> fraction,
                           std::function<std::string()> extra)
    : progress_(std::move(job)),
      fraction_(std::move(fraction)),
      extra_(std::move(extra)),
      period_ns_(PeriodFromRateHz(10.0)) {}

void ProgressLine::OnStepEnd(const sim::TruthSample& truth, bool last) {
  if (truth.stamp_ns % period_ns_ != 0 && !last) return;
  progress_.Update(truth.stamp_ns, fraction_(), extra_ ? extra_() : std::string());
  if (last) progress_.Finish();
}

}  // namespace corridorsim
