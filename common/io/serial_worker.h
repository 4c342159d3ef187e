#pragma once
// One background thread that runs jobs in the order they were submitted (e.g. encoding and
// writing exported frames while the next frames render). The order is what keeps outputs
// byte-identical: the jobs see exactly the calls they would have seen inline. Each job has a
// weight (e.g. 1 for a job holding a camera frame, 0 for a small one); Submit blocks while the
// queued weight is `max_pending_weight`, which bounds the memory of queued frames.
// An exception thrown by a job is rethrown by the next Submit or by Drain.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace corridorsim {

class SerialWorker {
 public:
  explicit SerialWorker(std::size_t max_pending_weight);
  ~SerialWorker();  // drains what is queued; swallows a pending exception (call Drain first)
  SerialWorker(const SerialWorker&) = delete;
  SerialWorker& operator=(const SerialWorker&) = delete;

  void Submit(std::function<void()> job, std::size_t weight = 1);
  /// Waits until every submitted job has run; rethrows the first exception of a job.
  void Drain();
  /// Seconds the worker spent running jobs (for the cost split).
  double busy_seconds() const;

 private:
  void Loop();
  void RethrowLocked(std::unique_lock<std::mutex>& lock);

  struct Job {
    std::function<void()> run;
    std::size_t weight = 1;
  };
  std::size_t max_pending_weight_;
  std::size_t pending_weight_ = 0;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Job> jobs_;
  bool running_job_ = false;
  bool stopping_ = false;
  std::exception_ptr error_;
  double busy_seconds_ = 0.0;
  std::thread thread_;
};

}  // namespace corridorsim
