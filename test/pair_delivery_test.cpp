// SPDX-License-Identifier: BSD-3-Clause
// PairDelivery under load: camera threads completing pairs concurrently, a slow receiver, clocks stepping back.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>
#include <vector>

#include "underwater_stereo/camera/pair_delivery.h"

using namespace underwater_stereo;

TEST(PairDelivery, PairsFromManyThreadsReachOneCallbackInStrictlyIncreasingCaptureTime) {
  constexpr int kThreads = 4, kPairsPerThread = 2000;
  std::mutex receiver_mutex;
  std::vector<std::int64_t> received;
  std::vector<std::uint64_t> sequences;
  std::atomic<int> inside{0}, concurrent{0};
  {
    PairDelivery delivery(
        [&](const StereoFrame& f) {
          if (inside.fetch_add(1) != 0) ++concurrent;
          if (f.capture_time_ns % 97 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));  // a slow one
          {
            std::lock_guard<std::mutex> lock(receiver_mutex);
            received.push_back(f.capture_time_ns);
            sequences.push_back(f.sequence);
          }
          inside.fetch_sub(1);
        },
        4);
    // As AravisStereoSource does: pairs are formed and pushed under one lock by whichever thread completes one.
    std::mutex pair_mutex;
    std::int64_t clock_ns = 1000;
    std::atomic<int> pushed{0};
    std::vector<std::thread> cameras;
    for (int t = 0; t < kThreads; ++t) {
      cameras.emplace_back([&, t] {
        for (int i = 0; i < kPairsPerThread; ++i) {
          std::lock_guard<std::mutex> lock(pair_mutex);
          StereoFrame f;
          clock_ns += 1000;
          // Now and then a camera clock re-synchronised after an outage stamps a pair in the past.
          f.capture_time_ns = (i % 500 == 499 && t == 0) ? clock_ns - 5000 : clock_ns;
          delivery.push(std::move(f));
          ++pushed;
        }
      });
    }
    for (auto& c : cameras) c.join();
    // Drained: every pair delivered or counted.
    for (int i = 0; i < 2000; ++i) {
      const auto c = delivery.counts();
      if (c.delivered + c.out_of_order + c.overflowed == static_cast<std::uint64_t>(pushed)) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    const auto c = delivery.counts();
    EXPECT_EQ(c.delivered + c.out_of_order + c.overflowed, static_cast<std::uint64_t>(kThreads * kPairsPerThread));
    EXPECT_EQ(c.out_of_order, 4U);  // the four stamps in the past
    std::lock_guard<std::mutex> lock(receiver_mutex);
    EXPECT_EQ(received.size(), c.delivered);
    std::cout << "delivered " << c.delivered << ", out of order " << c.out_of_order << ", overflowed " << c.overflowed
              << std::endl;
  }
  EXPECT_EQ(concurrent.load(), 0) << "the callback ran on two threads at once";
  ASSERT_FALSE(received.empty());
  for (std::size_t k = 1; k < received.size(); ++k) {
    ASSERT_LT(received[k - 1], received[k]) << "pair " << k << " out of capture order";
    ASSERT_EQ(sequences[k], k);
  }
}

TEST(PairDelivery, NoCallbackRunsAfterItIsDestroyed) {
  std::atomic<bool> destroyed{false}, late{false};
  std::atomic<int> calls{0};
  {
    PairDelivery delivery(
        [&](const StereoFrame&) {
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
          if (destroyed) late = true;
          ++calls;
        },
        8);
    for (int i = 0; i < 100; ++i) {
      StereoFrame f;
      f.capture_time_ns = i + 1;
      delivery.push(std::move(f));
    }
  }
  destroyed = true;
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_FALSE(late);
  EXPECT_LE(calls.load(), 100);
}
