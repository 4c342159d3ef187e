// Tests common/serial_worker.cpp: jobs run in submission order on one thread, a failing job's
// exception reaches the submitter, and the queued weight stays bounded.
#include "common/io/serial_worker.h"

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

TEST_CASE("serial worker runs jobs in submission order", "[worker]") {
  std::vector<int> order;  // touched by the worker thread only until Drain
  SerialWorker worker(2);
  for (int i = 0; i < 200; ++i) worker.Submit([&order, i] { order.push_back(i); }, i % 3 == 0);
  worker.Drain();
  REQUIRE(order.size() == 200);
  for (int i = 0; i < 200; ++i) CHECK(order[static_cast<std::size_t>(i)] == i);
  CHECK(worker.busy_seconds() >= 0.0);
}

TEST_CASE("serial worker never holds more queued weight than its bound", "[worker]") {
  std::atomic<int> queued{0};
  std::atomic<int> most{0};
  SerialWorker worker(3);
  for (int i = 0; i < 50; ++i) {
    const int now = ++queued;
    int seen = most.load();
    while (now > seen && !most.compare_exchange_weak(seen, now)) {
    }
    worker.Submit([&queued] {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      --queued;
    });
  }
  worker.Drain();
  // Three waiting plus the one running, at most.
  CHECK(most.load() <= 4);
  CHECK(queued.load() == 0);
}

TEST_CASE("a failing job's exception is rethrown and the jobs after it are skipped", "[worker]") {
  std::atomic<int> ran{0};
  SerialWorker worker(8);
  worker.Submit([&ran] { ++ran; });
  worker.Submit([] { throw std::runtime_error("disk full"); });
  bool thrown = false;
  try {
    for (int i = 0; i < 100; ++i) worker.Submit([&ran] { ++ran; });
    worker.Drain();
  } catch (const std::runtime_error& e) {
    thrown = std::string(e.what()) == "disk full";
  }
  CHECK(thrown);
  worker.Drain();  // the error was reported once; the worker is idle again
  CHECK(ran.load() < 101);
}

}  // namespace
}  // namespace corridorsim
