#include "harness/study/suite_runner.h"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>
#include <thread>

namespace corridorsim {

std::vector<SuiteCommandResult> RunSuiteCommands(const std::vector<SuiteCommand>& commands,
                                                 int jobs) {
  using Clock = std::chrono::steady_clock;
  struct Active {
    std::size_t index;
    std::unique_ptr<ChildProcess> child;
    Clock::time_point start;
  };
  std::vector<SuiteCommandResult> results(commands.size());
  std::vector<Active> active;
  std::size_t next = 0;
  while (next < commands.size() || !active.empty()) {
    if (const int signal = StopSignal()) {
      for (Active& a : active) a.child->Signal(signal);
      for (Active& a : active) a.child->Wait();
      std::fprintf(stderr, "corridorsim: test stopped by signal %d (%s); no report written\n",
                   signal, ::strsignal(signal));
      DieOfSignal(signal);
    }
    while (static_cast<int>(active.size()) < jobs && next < commands.size()) {
      const SuiteCommand& command = commands[next];
      std::printf("test: [%zu/%zu] %s\n", next + 1, commands.size(), command.label.c_str());
      std::fflush(stdout);
      active.push_back(
          {next, std::make_unique<ChildProcess>(command.argv, command.log.string()), Clock::now()});
      ++next;
    }
    bool ended = false;
    for (auto it = active.begin(); it != active.end();) {
      const std::optional<ChildStatus> status = it->child->Poll();
      if (!status) {
        ++it;
        continue;
      }
      results[it->index] = {*status,
                            std::chrono::duration<double>(Clock::now() - it->start).count()};
      it = active.erase(it);
      ended = true;
    }
    // Polled as `study` polls its runs: a file's job takes seconds to hours.
    if (!ended) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return results;
}

}  // namespace corridorsim
