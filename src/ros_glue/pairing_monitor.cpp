// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/pairing_monitor.h"

#include <cmath>
#include <limits>

#include <opencv2/core.hpp>

namespace underwater_stereo {
namespace ros_glue {

void PairingMonitor::image(StereoSide side, double stamp_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto& seen = seen_[static_cast<int>(side)];
  seen.push_back({stamp_s, false});
  while (seen.size() > window_) evict(side);
}

void PairingMonitor::paired(double left_stamp_s, double right_stamp_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (auto [side, stamp] : {std::pair<int, double>{0, left_stamp_s}, {1, right_stamp_s}}) {
    for (Seen& s : seen_[side]) {
      if (s.stamp_s == stamp) s.paired = true;
    }
  }
}

PairingMonitor::Counts PairingMonitor::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counts_;
}

void PairingMonitor::evict(StereoSide side) {
  auto& seen = seen_[static_cast<int>(side)];
  const Seen oldest = seen.front();
  seen.pop_front();
  if (oldest.paired) return;
  const bool left = side == StereoSide::kLeft;
  (left ? counts_.unpaired_left : counts_.unpaired_right) += 1;
  double nearest = std::numeric_limits<double>::infinity();
  for (const Seen& other : seen_[left ? 1 : 0]) {
    if (std::abs(other.stamp_s - oldest.stamp_s) < std::abs(nearest)) nearest = other.stamp_s - oldest.stamp_s;
  }
  counts_.last = std::string(left ? "left" : "right") + " image " + cv::format("%.6f", oldest.stamp_s) +
                 " never paired: " +
                 (std::isfinite(nearest) ? "the nearest " + std::string(left ? "right" : "left") + " image is " +
                                               cv::format("%+.3f", nearest * 1000.0) + " ms away"
                                         : "no " + std::string(left ? "right" : "left") + " image seen near it");
}

}  // namespace ros_glue
}  // namespace underwater_stereo
