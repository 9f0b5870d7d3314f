// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A pool of worker threads that processes jobs in parallel and hands their results on in the order the
/// jobs were submitted (the detector nodelet's stereo pairs; no ROS here, so the scheduling is gtested alone).

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace underwater_stereo {

/// Where a job's exception was thrown.
enum class PoolStage {
  kProcess,  ///< in the process function: the job gives no result, later results are still delivered
  kDeliver,  ///< in the deliver function: that result is lost, later ones are still delivered
};

/// Workers that each take a job, run `process` on it, and a `deliver` that receives the results one at a
/// time in submission order (a worker that finishes early leaves its result and takes the next job; whichever
/// worker completes the job next in line delivers every result then ready, so no thread is added for it).
///
/// A submitted job goes to the worker idle last (its caches are the warmest); while all are busy up to
/// `max_waiting` jobs wait, and beyond that the oldest waiting job is dropped and counted: the freshest jobs
/// are the useful ones. `submit` never waits for a worker. An exception from `process` or `deliver` goes to
/// `on_error` with its message and never ends a worker. `stop()` (also the destructor) lets the running jobs
/// and deliveries finish, discards the waiting jobs and the results not yet delivered, and joins the workers.
///
/// @tparam Job     moved in by `submit`, handed to `process` by reference
/// @tparam Result  what `process` returns and `deliver` receives
template <typename Job, typename Result>
class OrderedWorkerPool {
 public:
  using Process = std::function<Result(Job&)>;  ///< runs on the workers, several jobs at once
  using Deliver = std::function<void(Result&)>;  ///< never two calls at once, in submission order
  using OnError = std::function<void(PoolStage, const std::string& what)>;  ///< must not throw

  /// Starts `workers` threads.
  /// @throw std::invalid_argument when `workers` < 1 or a function is empty
  OrderedWorkerPool(int workers, std::size_t max_waiting, Process process, Deliver deliver, OnError on_error)
      : max_waiting_(max_waiting),
        process_(std::move(process)),
        deliver_(std::move(deliver)),
        on_error_(std::move(on_error)) {
    if (workers < 1) throw std::invalid_argument("OrderedWorkerPool: workers must be at least 1, not " + std::to_string(workers));
    if (!process_ || !deliver_ || !on_error_) {
      throw std::invalid_argument("OrderedWorkerPool: process, deliver and on_error must all be given");
    }
    for (int i = 0; i < workers; ++i) slots_.push_back(std::make_unique<Slot>());
    for (int i = 0; i < workers; ++i) threads_.emplace_back([this, i] { work(static_cast<std::size_t>(i)); });
  }

  OrderedWorkerPool(const OrderedWorkerPool&) = delete;
  OrderedWorkerPool& operator=(const OrderedWorkerPool&) = delete;

  ~OrderedWorkerPool() { stop(); }

  /// Queues `job` (never blocks on a worker); after stop() it is discarded.
  void submit(Job job) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) return;
    if (!idle_.empty()) {
      Slot& slot = *slots_[idle_.back()];
      idle_.pop_back();
      slot.job = std::move(job);
      slot.turn = next_turn_++;
      slot.wake.notify_one();
      return;
    }
    waiting_.push_back(std::move(job));
    if (waiting_.size() > max_waiting_) {
      waiting_.pop_front();
      ++dropped_;
    }
  }

  /// Jobs dropped so far because more than `max_waiting` waited while every worker was busy.
  std::uint64_t dropped() const { return dropped_; }

  /// Ends the pool as the class comment says; idempotent. Not from within `process` or `deliver`.
  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
      waiting_.clear();
    }
    for (auto& slot : slots_) slot->wake.notify_all();
    for (std::thread& t : threads_) {
      if (t.joinable()) t.join();
    }
  }

 private:
  /// A job handed to an idle worker, with its turn.
  struct Slot {
    std::condition_variable wake;
    std::optional<Job> job;
    std::uint64_t turn = 0;
  };

  void work(std::size_t index) {
    Slot& slot = *slots_[index];
    while (true) {
      std::optional<Job> job;
      std::uint64_t turn = 0;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        if (stopping_) return;
        if (!waiting_.empty()) {  // arrived while every worker was busy
          job = std::move(waiting_.front());
          waiting_.pop_front();
          turn = next_turn_++;
        } else {
          idle_.push_back(index);
          slot.wake.wait(lock, [&] { return stopping_ || slot.job.has_value(); });
          if (stopping_) return;
          job = std::move(slot.job);
          slot.job.reset();
          turn = slot.turn;
        }
      }
      std::optional<Result> result;
      try {
        result.emplace(process_(*job));
      } catch (const std::exception& e) {
        on_error_(PoolStage::kProcess, e.what());
      } catch (...) {
        on_error_(PoolStage::kProcess, "an exception not derived from std::exception");
      }
      std::unique_lock<std::mutex> lock(mutex_);
      finished_.emplace(turn, std::move(result));
      if (stopping_) return;
      if (delivering_) continue;  // the worker delivering takes this result too when its turn comes
      delivering_ = true;
      for (auto next = finished_.find(delivery_turn_); next != finished_.end(); next = finished_.find(delivery_turn_)) {
        std::optional<Result> ready = std::move(next->second);
        finished_.erase(next);
        ++delivery_turn_;
        lock.unlock();
        if (ready) deliverOne(*ready);
        lock.lock();
        if (stopping_) break;
      }
      delivering_ = false;
    }
  }

  void deliverOne(Result& result) {
    try {
      deliver_(result);
    } catch (const std::exception& e) {
      on_error_(PoolStage::kDeliver, e.what());
    } catch (...) {
      on_error_(PoolStage::kDeliver, "an exception not derived from std::exception");
    }
  }

  const std::size_t max_waiting_;
  const Process process_;
  const Deliver deliver_;
  const OnError on_error_;

  std::mutex mutex_;  ///< guards everything below but the threads and the count
  std::vector<std::unique_ptr<Slot>> slots_;
  std::vector<std::size_t> idle_;  ///< idle workers, the latest last
  std::deque<Job> waiting_;        ///< jobs that arrived while every worker was busy, oldest first
  bool stopping_ = false;
  std::uint64_t next_turn_ = 0, delivery_turn_ = 0;
  std::map<std::uint64_t, std::optional<Result>> finished_;  ///< results (none: process threw) awaiting their turn
  bool delivering_ = false;                                   ///< a worker is delivering finished_ in order
  std::atomic<std::uint64_t> dropped_{0};
  std::vector<std::thread> threads_;
};

}  // namespace underwater_stereo
