// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/pair_delivery.h"

#include <utility>

namespace underwater_stereo {

PairDelivery::PairDelivery(StereoSource::FrameCallback callback, std::size_t max_queued)
    : callback_(std::move(callback)), max_queued_(max_queued), thread_([this] { run(); }) {}

PairDelivery::~PairDelivery() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void PairDelivery::push(StereoFrame pair) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (pair.capture_time_ns <= last_capture_ns_) {
      ++counts_.out_of_order;
      return;
    }
    last_capture_ns_ = pair.capture_time_ns;
    queue_.push_back(std::move(pair));
    if (queue_.size() > max_queued_) {
      queue_.pop_front();
      ++counts_.overflowed;
    }
  }
  wake_.notify_one();
}

PairDelivery::Counts PairDelivery::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counts_;
}

void PairDelivery::run() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (stopping_) return;
    StereoFrame pair = std::move(queue_.front());
    queue_.pop_front();
    pair.sequence = counts_.delivered++;
    lock.unlock();
    if (callback_) callback_(pair);
    lock.lock();
  }
}

}  // namespace underwater_stereo
