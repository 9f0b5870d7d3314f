// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Independent pieces of one pair's work shared out over a few threads of the detector's own.
///
/// Used instead of OpenCV's pool (cv::parallel_for_) where the detector wants a second core for one pair's
/// latency while OpenCV itself runs single-threaded (cv::setNumThreads(1) in a busy nodelet manager, where its
/// pool's threads spin between loops and fight the other workers for the cores).

#include <atomic>
#include <exception>
#include <future>
#include <system_error>
#include <vector>

namespace underwater_stereo {

/// Calls work(i) once for every i in [0, n): on the calling thread and on up to threads - 1 more, each taking
/// the next index not yet taken (so which thread ran an index changes nothing the caller sees, as long as
/// work(i) touches only what belongs to i). Runs everything on the calling thread when threads <= 1, n <= 1,
/// or no thread can be started. Returns when every index is done; an exception thrown by work is rethrown
/// then (the first one, by thread).
template <typename Work>
void workOnThreads(int n, int threads, Work&& work) {
  std::atomic<int> next{0};
  std::atomic<bool> failed{false};
  auto drain = [&] {
    for (int i; !failed.load(std::memory_order_relaxed) && (i = next.fetch_add(1)) < n;) {
      try {
        work(i);
      } catch (...) {
        failed = true;
        throw;
      }
    }
  };
  std::vector<std::future<void>> helpers;
  for (int t = 1; t < threads && t < n; ++t) {
    try {
      helpers.push_back(std::async(std::launch::async, drain));
    } catch (const std::system_error&) {
      break;  // no thread to be had: the ones started (and this one) do the rest
    }
  }
  std::exception_ptr error;
  try {
    drain();
  } catch (...) {
    error = std::current_exception();
  }
  for (std::future<void>& h : helpers) {
    try {
      h.get();
    } catch (...) {
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace underwater_stereo
