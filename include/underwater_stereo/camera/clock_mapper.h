// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Device timestamps -> host time, with a filtered offset.

#include <cstdint>
#include <deque>

namespace underwater_stereo {

/// Each frame carries the camera's timestamp (its own clock) and the host's receive time, which adds a
/// transfer delay of varying length. host - device is therefore the true offset plus a positive delay: the
/// smallest value over a recent window estimates the offset best, and device + offset is the capture time
/// on the host clock, free of the transfer jitter.
class ClockMapper {
 public:
  /// `window`: how many recent frames the minimum is taken over (drift is followed over that span).
  explicit ClockMapper(std::size_t window = 64);

  /// The capture time on the host clock [ns] for a frame with these timestamps. A device clock that
  /// jumps backwards (camera restarted) or a device timestamp of 0 (camera without one) restarts the
  /// filter; without a device timestamp the host time is returned as it is.
  std::int64_t toHost(std::uint64_t device_ns, std::int64_t host_ns);

  /// The current offset estimate [ns] (host - device); 0 before the first frame.
  std::int64_t offsetNs() const { return offset_; }

 private:
  std::size_t window_;
  std::deque<std::int64_t> offsets_;
  std::uint64_t last_device_ = 0;
  std::int64_t offset_ = 0;
};

}  // namespace underwater_stereo
