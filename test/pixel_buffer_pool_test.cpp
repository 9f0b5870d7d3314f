// SPDX-License-Identifier: BSD-3-Clause
// PixelBufferPool: buffers are recycled, never handed out twice, keep their bytes while held, and the pool keeps
// at most max_free of them.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "underwater_stereo/camera/pixel_buffer_pool.h"

using underwater_stereo::PixelBufferPool;

TEST(PixelBufferPool, ReleasedBufferIsRecycledWithoutAllocating) {
  PixelBufferPool pool(4);
  const std::uint8_t* first = nullptr;
  for (int frame = 0; frame < 100; ++frame) {  // one frame in flight at a time: one buffer carries them all
    auto buffer = pool.acquire(1000);
    ASSERT_EQ(buffer->size(), 1000U);
    if (!first) first = buffer->data();
    EXPECT_EQ(buffer->data(), first);
  }
  EXPECT_EQ(pool.allocations(), 1U);
  EXPECT_EQ(pool.freeBuffers(), 1U);
}

TEST(PixelBufferPool, HeldBuffersKeepTheirBytesAndAreNeverHandedOutTwice) {
  PixelBufferPool pool(8);
  std::vector<PixelBufferPool::Buffer> held;
  for (int i = 0; i < 6; ++i) {
    held.push_back(pool.acquire(64));
    std::fill(held.back()->begin(), held.back()->end(), static_cast<std::uint8_t>(i + 1));
  }
  std::set<const std::uint8_t*> storage;
  for (const auto& b : held) storage.insert(b->data());
  EXPECT_EQ(storage.size(), held.size());
  for (int round = 0; round < 20; ++round) {  // other frames come and go while those six are held
    auto other = pool.acquire(64);
    EXPECT_EQ(storage.count(other->data()), 0U);
    std::fill(other->begin(), other->end(), std::uint8_t{0xEE});
  }
  for (int i = 0; i < 6; ++i) {
    EXPECT_TRUE(std::all_of(held[i]->begin(), held[i]->end(), [i](std::uint8_t v) { return v == i + 1; })) << i;
  }
}

TEST(PixelBufferPool, KeepsAtMostMaxFreeBuffers) {
  PixelBufferPool pool(3);
  {
    std::vector<PixelBufferPool::Buffer> burst;
    for (int i = 0; i < 10; ++i) burst.push_back(pool.acquire(256));
  }  // ten in flight at once, all released
  EXPECT_EQ(pool.freeBuffers(), 3U);
  EXPECT_EQ(pool.allocations(), 10U);
  {
    std::vector<PixelBufferPool::Buffer> again;
    for (int i = 0; i < 3; ++i) again.push_back(pool.acquire(256));
  }
  EXPECT_EQ(pool.allocations(), 10U) << "three kept, three reused";
}

TEST(PixelBufferPool, SizeChangeAllocatesAndStaleSizesAgeOut) {
  PixelBufferPool pool(2);
  pool.acquire(100);
  EXPECT_EQ(pool.freeBuffers(), 1U);
  {
    auto a = pool.acquire(200), b = pool.acquire(200);
    EXPECT_EQ(a->size(), 200U);
  }
  EXPECT_EQ(pool.allocations(), 3U) << "no 200-byte buffer was free";
  EXPECT_EQ(pool.freeBuffers(), 2U);
  pool.acquire(200);
  pool.acquire(200);
  EXPECT_EQ(pool.allocations(), 3U) << "the 100-byte buffer was the one evicted";
}

TEST(PixelBufferPool, BufferEmptiedByItsHolderIsFreedNotKept) {
  PixelBufferPool pool(4);
  {
    auto buffer = pool.acquire(128);
    std::vector<std::uint8_t> taken = std::move(*buffer);  // a receiver took the storage and kept it
  }
  EXPECT_EQ(pool.freeBuffers(), 0U);
  {
    auto buffer = pool.acquire(128);
    std::vector<std::uint8_t> message;
    message.swap(*buffer);  // lent to a message...
    buffer->swap(message);  // ...and given back when it was done
  }
  EXPECT_EQ(pool.freeBuffers(), 1U);
}

TEST(PixelBufferPool, BuffersMayOutliveThePool) {
  PixelBufferPool::Buffer survivor;
  {
    PixelBufferPool pool(4);
    survivor = pool.acquire(512);
    pool.acquire(512);
  }
  (*survivor)[511] = 7;  // still valid; freed (not returned) when released, under ASan without a leak
  survivor.reset();
  EXPECT_THROW(PixelBufferPool(0), std::invalid_argument);
}

TEST(PixelBufferPool, ConcurrentAcquireAndReleaseNeverSharesABuffer) {
  PixelBufferPool pool(16);
  std::vector<std::thread> threads;
  std::atomic<int> clashes{0};
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&pool, &clashes, t] {
      for (int i = 0; i < 2000; ++i) {
        auto b = pool.acquire(32);
        std::fill(b->begin(), b->end(), static_cast<std::uint8_t>(t));
        if (std::any_of(b->begin(), b->end(), [t](std::uint8_t v) { return v != t; })) ++clashes;
      }
    });
  }
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(clashes.load(), 0);
  EXPECT_LE(pool.allocations(), 4U);
}
