// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/frame_id_tracker.h"

namespace underwater_stereo {

std::uint32_t FrameIdTracker::missedBefore(std::uint32_t frame_id) {
  constexpr std::uint32_t kIds = 65535;  // 1..65535
  const std::uint32_t id = frame_id & 0xFFFFU;
  if (id == 0 || previous_ == 0) {
    previous_ = id;
    return 0;
  }
  // Steps forward from previous_ to id on the ring 1..65535.
  const std::uint32_t steps = (id + kIds - previous_) % kIds;
  previous_ = id;
  if (steps == 0 || steps > kIds / 2) return 0;  // repeated id, or a restart (big jump backwards)
  const std::uint32_t missed = steps - 1;
  total_missed_ += missed;
  return missed;
}

}  // namespace underwater_stereo
