// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Hands stereo pairs formed on several camera threads to one callback thread, in capture order.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <thread>

#include "underwater_stereo/camera/stereo_source.h"

namespace underwater_stereo {

/// One delivery thread that calls the callback with every pushed pair, one at a time, in the order they
/// were pushed; a pair whose capture time is not after the previous pair's (a camera clock re-synchronised
/// after an outage) is dropped and counted, so receivers see strictly increasing stamps. A callback slower
/// than the cameras leaves at most `max_queued` pairs waiting: the oldest is dropped and counted. Pairs get
/// their `sequence` here (pairs delivered, from 0). Thread-safe.
class PairDelivery {
 public:
  PairDelivery(StereoSource::FrameCallback callback, std::size_t max_queued);
  /// Stops; pairs still queued are discarded.
  ~PairDelivery();
  PairDelivery(const PairDelivery&) = delete;
  PairDelivery& operator=(const PairDelivery&) = delete;

  void push(StereoFrame pair);

  struct Counts {
    std::uint64_t delivered = 0;
    std::uint64_t out_of_order = 0;  ///< dropped: capture time not after the previous pair's
    std::uint64_t overflowed = 0;    ///< dropped: the callback was still busy with earlier pairs
  };
  Counts counts() const;

 private:
  void run();

  StereoSource::FrameCallback callback_;
  const std::size_t max_queued_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<StereoFrame> queue_;
  std::int64_t last_capture_ns_ = INT64_MIN;
  Counts counts_;
  bool stopping_ = false;
  std::thread thread_;  ///< last: starts once everything above exists
};

}  // namespace underwater_stereo
