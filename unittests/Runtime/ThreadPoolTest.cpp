//===- ThreadPoolTest.cpp --------------------------------------------------===//

#include "OslRuntime/ThreadPool.h"

#include "gtest/gtest.h"

#include <atomic>
#include <vector>

using namespace osl;

TEST(ThreadPool, RunsEveryTaskOnce) {
  for (int threads : {1, 2, 3}) {
    ThreadPool pool(threads);
    EXPECT_EQ(pool.size(), threads);
    for (int round = 0; round < 20; ++round) {
      std::vector<std::atomic<int>> runs(257);
      std::atomic<int> badWorker{0};
      pool.parallelForWithWorker(257, [&](int task, int worker) {
        runs[task]++;
        if (worker < 0 || worker >= threads)
          badWorker++;
      });
      for (auto &r : runs)
        ASSERT_EQ(r.load(), 1);
      EXPECT_EQ(badWorker.load(), 0);
    }
  }
}

TEST(ThreadPool, ZeroMeansHardwareConcurrency) {
  ThreadPool pool(0);
  unsigned hw = std::thread::hardware_concurrency();
  EXPECT_EQ(pool.size(), hw ? int(hw) : 1);
}

TEST(ThreadPool, EmptyAndNestedLoops) {
  ThreadPool pool(2);
  pool.parallelFor(0, [](int) { FAIL(); });
  std::atomic<int> inner{0};
  pool.parallelFor(4, [&](int) {
    pool.parallelFor(3, [&](int) { inner++; });
  });
  EXPECT_EQ(inner.load(), 12);
}
