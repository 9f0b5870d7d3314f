// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The distinct problems of the last few seconds, for a diagnostic summary (ROS-free: times as seconds).

#include <cstddef>
#include <deque>
#include <mutex>
#include <string>

namespace underwater_stereo {
namespace ros_glue {

/// Keeps each distinct problem with the last time it was seen, so that two kinds of bad input that arrive
/// within `hold_s` both reach the diagnostic summary instead of the later one hiding the earlier (pairs are
/// refused on several worker threads, in any order). Thread-safe.
class RecentProblems {
 public:
  /// `hold_s`: how long a problem stays in the summary; `max_kinds`: at most this many are named.
  RecentProblems(double hold_s, std::size_t max_kinds) : hold_s_(hold_s), max_kinds_(max_kinds) {}

  void add(const std::string& what, double now_s);
  /// The problems seen within `hold_s` of `now_s`, newest first, joined by "; " (at most `max_kinds`, then
  /// "and N more"); empty when there are none.
  std::string summary(double now_s) const;
  /// The last problem ever seen ("" when none): kept after it leaves the summary.
  std::string last() const;
  long count() const;

 private:
  struct Seen {
    std::string what;
    double time_s;
  };
  const double hold_s_;
  const std::size_t max_kinds_;
  mutable std::mutex mutex_;
  std::deque<Seen> seen_;  ///< newest first, one entry per distinct message, pruned to the hold window on add
  std::string last_;
  long count_ = 0;
};

}  // namespace ros_glue
}  // namespace underwater_stereo
