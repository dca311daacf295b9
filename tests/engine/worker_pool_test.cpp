// worker_pool_test.cpp — the parallel-for: every index once, whatever the thread count, and an exception thrown in
// any thread reaches the caller once all threads are done.
#include "engine/core/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <vector>

TEST(WorkerPool, EveryIndexRunsOnceOnAnyThreadCount) {
  for (int threads : {1, 2, 3}) {
    engine::WorkerPool pool(threads);
    std::vector<int> hits(10, 0);
    pool.parallelFor(10, [&](int i) { ++hits[size_t(i)]; });
    EXPECT_EQ(hits, std::vector<int>(10, 1)) << threads << " threads";
  }
}

TEST(WorkerPool, AnExceptionInAnyThreadReachesTheCallerAfterTheOthersFinish) {
  engine::WorkerPool pool(2);
  for (int failing : {0, 9}) {  // index 0 is the caller's block, index 9 a worker's
    std::atomic<int> done{0};
    EXPECT_THROW(pool.parallelFor(10,
                                  [&](int i) {
                                    if (i == failing) throw std::runtime_error("diverged");
                                    ++done;
                                  }),
                 std::runtime_error);
    // the other thread's block ran to its end: 5 indices, less the failing one if it was there
    EXPECT_GE(done.load(), 4) << "failing index " << failing;
  }
  // the pool is usable again, and an earlier error does not come back
  int sum = 0;
  pool.parallelFor(1, [&](int i) { sum += i + 1; });
  std::atomic<int> count{0};
  pool.parallelFor(10, [&](int) { ++count; });
  EXPECT_EQ(sum, 1);
  EXPECT_EQ(count.load(), 10);
}
