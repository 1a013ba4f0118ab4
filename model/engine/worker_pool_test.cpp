// The threads that run the PE engines side by side (engine/worker_pool.h): every job once, on
// several threads, batch after batch, and a job's failure reported the same way whatever the
// threads' timing.
#include "engine/worker_pool.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace rtm {
namespace {

TEST(WorkerPool, RunsEveryJobOnceBatchAfterBatch) {
  WorkerPool pool(3);
  EXPECT_EQ(pool.threads(), 3);
  for (size_t n : {0, 1, 2, 7, 64}) {
    for (int batch = 0; batch < 50; ++batch) {
      std::vector<std::atomic<int>> runs(n);
      pool.run(n, [&](size_t i) { ++runs[i]; });
      for (size_t i = 0; i < n; ++i) ASSERT_EQ(runs[i].load(), 1) << "job " << i << " of " << n;
    }
  }
}

TEST(WorkerPool, SpreadsABatchOverItsThreads) {
  WorkerPool pool(2);
  std::mutex m;
  std::set<std::thread::id> seen;
  std::atomic<int> waiting{0};
  // Each of the two jobs waits for the other to start: only two threads at once can finish them.
  pool.run(2, [&](size_t) {
    ++waiting;
    while (waiting.load() < 2) std::this_thread::yield();
    std::lock_guard<std::mutex> lock(m);
    seen.insert(std::this_thread::get_id());
  });
  EXPECT_EQ(seen.size(), 2u);
}

TEST(WorkerPool, OneThreadRunsTheJobsInOrderItself) {
  WorkerPool pool(1);
  std::vector<size_t> order;
  const std::thread::id caller = std::this_thread::get_id();
  pool.run(5, [&](size_t i) {
    EXPECT_EQ(std::this_thread::get_id(), caller);
    order.push_back(i);
  });
  EXPECT_EQ(order, (std::vector<size_t>{0, 1, 2, 3, 4}));
}

TEST(WorkerPool, AFailingJobLetsTheOthersFinishAndTheLowestFailureIsRethrown) {
  for (int threads : {1, 2, 4}) {
    WorkerPool pool(threads);
    std::vector<std::atomic<int>> runs(16);
    try {
      pool.run(16, [&](size_t i) {
        ++runs[i];
        if (i == 5 || i == 11) throw std::runtime_error("job " + std::to_string(i));
      });
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "job 5") << threads << " threads";
    }
    for (size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(runs[i].load(), 1) << "job " << i;
    std::atomic<int> after{0};
    pool.run(3, [&](size_t) { ++after; });  // still usable
    EXPECT_EQ(after.load(), 3);
  }
}

TEST(WorkerPool, ZeroThreadsMeansOnePerCore) {
  WorkerPool pool(0);
  EXPECT_EQ(pool.threads(), int(std::max(1u, std::thread::hardware_concurrency())));
}

}  // namespace
}  // namespace rtm
