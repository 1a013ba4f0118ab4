#include "engine/worker_pool.h"

#include <algorithm>

namespace rtm {

WorkerPool::WorkerPool(int threads) {
  if (threads <= 0) threads = int(std::max(1u, std::thread::hardware_concurrency()));
  for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { work(); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  start_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void WorkerPool::take_jobs() {
  for (size_t i; (i = next_.fetch_add(1, std::memory_order_relaxed)) < jobs_;) {
    try {
      (*job_)(i);
    } catch (...) {
      errors_[i] = std::current_exception();
    }
  }
}

void WorkerPool::run(size_t n, const std::function<void(size_t)>& job) {
  if (n == 0) return;
  errors_.assign(n, nullptr);
  const bool alone = workers_.empty() || n == 1;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    job_ = &job;
    jobs_ = n;
    next_ = 0;
    if (!alone) {
      working_ = workers_.size();
      ++batch_;
    }
  }
  if (!alone) start_.notify_all();
  take_jobs();
  if (!alone) {
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return working_ == 0; });
  }
  for (const std::exception_ptr& e : errors_)
    if (e) std::rethrow_exception(e);
}

void WorkerPool::work() {
  uint64_t seen = 0;
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      start_.wait(lock, [&] { return stopping_ || batch_ != seen; });
      if (stopping_) return;
      seen = batch_;
    }
    take_jobs();
    std::lock_guard<std::mutex> lock(mutex_);
    if (--working_ == 0) done_.notify_one();
  }
}

}  // namespace rtm
