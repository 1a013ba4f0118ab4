// A fixed set of threads that runs batches of independent jobs: the PE engines of one simulated
// instant (machine/engine_driver.h). Plain C++, no SystemC: the jobs must not touch the kernel.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace rtm {

class WorkerPool {
 public:
  /// `threads` in all, the caller of run() included (0: one per core); with one, run() runs the
  /// jobs itself, in order.
  explicit WorkerPool(int threads);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  int threads() const { return int(workers_.size()) + 1; }

  /// Runs job(i) for every i below n, spread over the threads, and returns once all have
  /// finished. A job that throws does not stop the others; afterwards the exception of the
  /// lowest-numbered job that threw is rethrown, so what the caller sees does not depend on the
  /// threads' timing.
  void run(size_t n, const std::function<void(size_t)>& job);

 private:
  void work();
  void take_jobs();

  std::mutex mutex_;
  std::condition_variable start_, done_;
  const std::function<void(size_t)>* job_ = nullptr;
  size_t jobs_ = 0;
  std::atomic<size_t> next_{0};
  size_t working_ = 0;  ///< workers still in the current batch
  uint64_t batch_ = 0;  ///< batches started: a worker waits for the next
  bool stopping_ = false;
  std::vector<std::exception_ptr> errors_;  ///< per job of the batch
  std::vector<std::thread> workers_;
};

}  // namespace rtm
