// SPDX-License-Identifier: BSD-3-Clause
// OrderedWorkerPool: results in submission order whatever the processing times, the oldest waiting job
// dropped and counted, a clean stop, exceptions reported and never ending a worker.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "underwater_stereo/common/ordered_worker_pool.h"

using namespace underwater_stereo;

namespace {

using Pool = OrderedWorkerPool<int, int>;

/// Holds the workers inside `process` until opened, so a test knows which jobs are running and which wait.
class Gate {
 public:
  void pass(int job) {
    std::unique_lock<std::mutex> lock(mutex_);
    inside_.push_back(job);
    changed_.notify_all();
    changed_.wait(lock, [&] { return open_; });
  }
  void waitInside(std::size_t n) {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return inside_.size() >= n; });
  }
  void open() {
    std::lock_guard<std::mutex> lock(mutex_);
    open_ = true;
    changed_.notify_all();
  }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::vector<int> inside_;
  bool open_ = false;
};

/// What deliver and on_error received.
struct Received {
  std::mutex mutex;
  std::vector<int> results;
  std::vector<std::pair<PoolStage, std::string>> errors;
  void add(int r) {
    std::lock_guard<std::mutex> lock(mutex);
    results.push_back(r);
  }
  void error(PoolStage stage, const std::string& what) {
    std::lock_guard<std::mutex> lock(mutex);
    errors.emplace_back(stage, what);
  }
};

}  // namespace

TEST(OrderedWorkerPool, DeliversEveryResultInSubmissionOrderOneAtATime) {
  for (int workers : {1, 2, 3, 5}) {
    constexpr int kJobs = 400;
    const unsigned seed = 1000u + static_cast<unsigned>(workers);
    std::mt19937 random(seed);
    std::vector<int> sleep_us(kJobs);
    for (int& s : sleep_us) s = std::uniform_int_distribution<int>(0, 300)(random);
    Received received;
    std::atomic<int> inside_deliver{0}, overlapping{0};
    {
      // max_waiting as large as the burst: nothing is dropped, so every job must come out.
      Pool pool(
          workers, kJobs, [&](int& job) {
            std::this_thread::sleep_for(std::chrono::microseconds(sleep_us[job]));
            return job * 10;
          },
          [&](int& r) {
            if (inside_deliver.fetch_add(1) != 0) ++overlapping;
            received.add(r);
            inside_deliver.fetch_sub(1);
          },
          [&](PoolStage s, const std::string& w) { received.error(s, w); });
      for (int i = 0; i < kJobs; ++i) pool.submit(i);
      while (true) {
        {
          std::lock_guard<std::mutex> lock(received.mutex);
          if (received.results.size() == kJobs) break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      EXPECT_EQ(pool.dropped(), 0u);
    }
    ASSERT_EQ(received.results.size(), static_cast<std::size_t>(kJobs)) << "workers " << workers << ", seed " << seed;
    for (int i = 0; i < kJobs; ++i) ASSERT_EQ(received.results[i], i * 10) << "workers " << workers << ", seed " << seed;
    EXPECT_EQ(overlapping, 0) << "deliver was called from two threads at once";
    EXPECT_TRUE(received.errors.empty());
  }
}

TEST(OrderedWorkerPool, DropsTheOldestWaitingJobsAndCountsThem) {
  Gate gate;
  Received received;
  {
    Pool pool(
        2, 3, [&](int& job) {
          gate.pass(job);
          return job;
        },
        [&](int& r) { received.add(r); }, [&](PoolStage s, const std::string& w) { received.error(s, w); });
    pool.submit(0);
    pool.submit(1);
    gate.waitInside(2);  // both workers busy: 2..9 wait, only the latest 3 are kept
    for (int i = 2; i < 10; ++i) pool.submit(i);
    EXPECT_EQ(pool.dropped(), 5u);
    gate.open();
    while (true) {
      {
        std::lock_guard<std::mutex> lock(received.mutex);
        if (received.results.size() == 5) break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    EXPECT_EQ(pool.dropped(), 5u);
  }
  EXPECT_EQ(received.results, (std::vector<int>{0, 1, 7, 8, 9}));
  EXPECT_TRUE(received.errors.empty());
}

TEST(OrderedWorkerPool, StopFinishesRunningJobsDiscardsWaitingOnesAndIgnoresLaterSubmits) {
  Gate gate;
  Received received;
  std::atomic<int> processed{0};
  Pool pool(
      1, 5, [&](int& job) {
        gate.pass(job);
        ++processed;
        return job;
      },
      [&](int& r) { received.add(r); }, [&](PoolStage s, const std::string& w) { received.error(s, w); });
  pool.submit(0);
  gate.waitInside(1);
  pool.submit(1);
  pool.submit(2);
  std::thread stopper([&] { pool.stop(); });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // stop() waits for the running job (not asserted)
  gate.open();
  stopper.join();
  EXPECT_EQ(processed, 1) << "a waiting job was processed after stop()";
  pool.submit(3);
  pool.stop();  // idempotent
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(processed, 1);
  EXPECT_LE(received.results.size(), 1u);
  EXPECT_EQ(pool.dropped(), 0u) << "jobs discarded by stop() are not counted as dropped";
}

TEST(OrderedWorkerPool, DestructorStopsIdleAndBusyWorkers) {
  Gate gate;
  auto pool = std::make_unique<Pool>(
      3, 1, [&](int& job) {
        gate.pass(job);
        return job;
      },
      [](int&) {}, [](PoolStage, const std::string&) {});
  pool->submit(0);
  gate.waitInside(1);
  std::thread opener([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    gate.open();
  });
  pool.reset();  // two idle workers and one inside process: returns once that one is done
  opener.join();
  SUCCEED();
}

TEST(OrderedWorkerPool, ExceptionsAreReportedWithTheirStageAndTheOtherResultsStillComeInOrder) {
  Received received;
  {
    Pool pool(
        3, 100, [](int& job) {
          if (job % 5 == 1) throw std::runtime_error("bad job " + std::to_string(job));
          if (job == 7) throw 42;  // not a std::exception
          return job;
        },
        [&](int& r) {
          if (r == 4) throw std::logic_error("cannot deliver 4");
          received.add(r);
        },
        [&](PoolStage s, const std::string& w) { received.error(s, w); });
    for (int i = 0; i < 12; ++i) pool.submit(i);
    while (true) {
      {
        std::lock_guard<std::mutex> lock(received.mutex);
        if (received.results.size() + received.errors.size() == 12) break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  }
  EXPECT_EQ(received.results, (std::vector<int>{0, 2, 3, 5, 8, 9, 10}));
  ASSERT_EQ(received.errors.size(), 5u);
  int process_errors = 0, deliver_errors = 0;
  for (const auto& [stage, what] : received.errors) {
    if (stage == PoolStage::kProcess) {
      ++process_errors;
      EXPECT_TRUE(what.rfind("bad job ", 0) == 0 || what == "an exception not derived from std::exception") << what;
    } else {
      ++deliver_errors;
      EXPECT_EQ(what, "cannot deliver 4");
    }
  }
  EXPECT_EQ(process_errors, 4);  // 1, 6, 11 and 7
  EXPECT_EQ(deliver_errors, 1);
}

TEST(OrderedWorkerPool, RefusesNoWorkersAndMissingFunctions) {
  const auto process = [](int& j) { return j; };
  const auto deliver = [](int&) {};
  const auto on_error = [](PoolStage, const std::string&) {};
  EXPECT_THROW(Pool(0, 1, process, deliver, on_error), std::invalid_argument);
  EXPECT_THROW(Pool(1, 1, nullptr, deliver, on_error), std::invalid_argument);
  EXPECT_THROW(Pool(1, 1, process, nullptr, on_error), std::invalid_argument);
  EXPECT_THROW(Pool(1, 1, process, deliver, nullptr), std::invalid_argument);
}
