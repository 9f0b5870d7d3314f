// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/recent_problems.h"

#include <algorithm>

namespace underwater_stereo {
namespace ros_glue {

void RecentProblems::add(const std::string& what, double now_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++count_;
  last_ = what;
  seen_.erase(std::remove_if(seen_.begin(), seen_.end(),
                             [&](const Seen& s) { return s.what == what || now_s - s.time_s >= hold_s_; }),
              seen_.end());
  seen_.push_front({what, now_s});
}

std::string RecentProblems::summary(double now_s) const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::string out;
  std::size_t named = 0, recent = 0;
  for (const Seen& s : seen_) {
    if (now_s - s.time_s >= hold_s_) continue;
    ++recent;
    if (named == max_kinds_) continue;
    out += (named++ == 0 ? "" : "; ") + s.what;
  }
  if (recent > named) out += "; and " + std::to_string(recent - named) + " more";
  return out;
}

std::string RecentProblems::last() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_;
}

long RecentProblems::count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return count_;
}

}  // namespace ros_glue
}  // namespace underwater_stereo
