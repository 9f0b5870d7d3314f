// SPDX-License-Identifier: BSD-3-Clause
// workOnThreads: every index exactly once whatever the threads, exceptions brought back to the caller.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "underwater_stereo/detection/work_on_threads.h"

using namespace underwater_stereo;

TEST(WorkOnThreads, EveryIndexExactlyOnce) {
  for (int threads : {0, 1, 2, 3, 8}) {
    for (int n : {0, 1, 2, 5, 100}) {
      std::vector<std::atomic<int>> calls(n);
      workOnThreads(n, threads, [&](int i) { ++calls[i]; });
      for (int i = 0; i < n; ++i) EXPECT_EQ(calls[i].load(), 1) << "index " << i << " of " << n << ", " << threads << " threads";
    }
  }
}

TEST(WorkOnThreads, OneThreadRunsEverythingOnTheCaller) {
  const std::thread::id caller = std::this_thread::get_id();
  std::set<std::thread::id> ran_on;
  workOnThreads(10, 1, [&](int) { ran_on.insert(std::this_thread::get_id()); });
  EXPECT_EQ(ran_on, std::set<std::thread::id>{caller});
}

TEST(WorkOnThreads, UsesMoreThanTheCallerWhenAsked) {
  // Each index waits until two threads have joined in (or gives up after a while): with two threads, both run.
  std::atomic<int> inside{0};
  std::atomic<bool> met{false};
  workOnThreads(2, 2, [&](int) {
    ++inside;
    for (int k = 0; k < 2000 && inside.load() < 2; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (inside.load() == 2) met = true;
  });
  EXPECT_TRUE(met.load());
}

TEST(WorkOnThreads, AnExceptionReachesTheCallerAfterEveryThreadStopped) {
  for (int threads : {1, 2, 4}) {
    std::atomic<int> running{0};
    EXPECT_THROW(workOnThreads(50, threads,
                               [&](int i) {
                                 ++running;
                                 std::this_thread::sleep_for(std::chrono::microseconds(200));
                                 --running;
                                 if (i == 7) throw std::runtime_error("index 7");
                               }),
                 std::runtime_error)
        << threads << " threads";
    EXPECT_EQ(running.load(), 0) << threads << " threads";
  }
}
