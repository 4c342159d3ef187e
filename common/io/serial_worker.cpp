#include "common/io/serial_worker.h"

#include <chrono>

namespace corridorsim {

SerialWorker::SerialWorker(std::size_t max_pending_weight)
    : max_pending_weight_(max_pending_weight < 1 ? 1 : max_pending_weight),
      thread_([this] { Loop(); }) {}

SerialWorker::~SerialWorker() {
  {
    std::unique_lock<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void SerialWorker::RethrowLocked(std::unique_lock<std::mutex>& lock) {
  if (!error_) return;
  std::exception_ptr error = error_;
  error_ = nullptr;
  lock.unlock();
  std::rethrow_exception(error);
}

void SerialWorker::Submit(std::function<void()> job, std::size_t weight) {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] {
    return weight == 0 || pending_weight_ + weight <= max_pending_weight_ || jobs_.empty() ||
           error_;
  });
  RethrowLocked(lock);
  pending_weight_ += weight;
  jobs_.push_back(Job{std::move(job), weight});
  changed_.notify_all();
}

void SerialWorker::Drain() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return (jobs_.empty() && !running_job_) || error_; });
  RethrowLocked(lock);
}

double SerialWorker::busy_seconds() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return busy_seconds_;
}

void SerialWorker::Loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return !jobs_.empty() || stopping_; });
    if (jobs_.empty()) return;  // stopping and nothing left
    Job job = std::move(jobs_.front());
    jobs_.pop_front();
    running_job_ = true;
    lock.unlock();
    const auto t0 = std::chrono::steady_clock::now();
    std::exception_ptr error;
    try {
      // After a job failed the rest are skipped: their outputs would be incomplete anyway.
      job.run();
    } catch (...) {
      error = std::current_exception();
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    lock.lock();
    busy_seconds_ += seconds;
    running_job_ = false;
    pending_weight_ -= job.weight;
    if (error && !error_) error_ = error;
    if (error_) {
      for (const Job& skipped : jobs_) pending_weight_ -= skipped.weight;
      jobs_.clear();
    }
    changed_.notify_all();
  }
}

}  // namespace corridorsim
