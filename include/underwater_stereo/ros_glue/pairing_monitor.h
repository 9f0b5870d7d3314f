// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Accounts for stereo images that a synchroniser never paired (ROS-free: stamps as seconds).

#include <cstddef>
#include <deque>
#include <mutex>
#include <string>

namespace underwater_stereo {
namespace ros_glue {

enum class StereoSide { kLeft, kRight };

/// Every image seen on either side and every pair formed, so an image that was never part of a pair is
/// counted once the synchroniser can no longer pair it (more than `window` newer images on its side),
/// with the stamp difference to the nearest image of the other side. Thread-safe.
class PairingMonitor {
 public:
  /// `window`: images per side the synchroniser keeps (its queue size) plus slack.
  explicit PairingMonitor(std::size_t window) : window_(window) {}

  void image(StereoSide side, double stamp_s);
  void paired(double left_stamp_s, double right_stamp_s);

  struct Counts {
    long unpaired_left = 0, unpaired_right = 0;
    std::string last;  ///< the last unpaired image: its side, stamp and the nearest other side's stamp difference
  };
  Counts counts() const;

 private:
  struct Seen {
    double stamp_s;
    bool paired;
  };
  void evict(StereoSide side);

  const std::size_t window_;
  mutable std::mutex mutex_;
  std::deque<Seen> seen_[2];  ///< per side, oldest first
  Counts counts_;
};

}  // namespace ros_glue
}  // namespace underwater_stereo
