// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Frames lost between two received ones, from GigE Vision block ids (16 bit, 0 is never used).

#include <cstdint>

namespace underwater_stereo {

class FrameIdTracker {
 public:
  /// Frames missed since the previous id: 0 for consecutive ids (65535 -> 1 wraps, skipping 0), the gap
  /// otherwise. A jump backwards of more than half the id range (camera restarted) or the first id
  /// restarts counting and returns 0. Ids outside 1..65535 are taken modulo 65536 (0 -> restart).
  std::uint32_t missedBefore(std::uint32_t frame_id);

  std::uint64_t totalMissed() const { return total_missed_; }

 private:
  std::uint32_t previous_ = 0;  ///< 0: nothing received yet
  std::uint64_t total_missed_ = 0;
};

}  // namespace underwater_stereo
