// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/clock_mapper.h"

#include <algorithm>
#include <stdexcept>

namespace underwater_stereo {

ClockMapper::ClockMapper(std::size_t window) : window_(window) {
  if (window_ == 0) throw std::invalid_argument("ClockMapper: the window must hold at least one frame");
}

std::int64_t ClockMapper::toHost(std::uint64_t device_ns, std::int64_t host_ns) {
  if (device_ns == 0) return host_ns;
  if (device_ns < last_device_) offsets_.clear();
  last_device_ = device_ns;
  offsets_.push_back(host_ns - static_cast<std::int64_t>(device_ns));
  if (offsets_.size() > window_) offsets_.pop_front();
  offset_ = *std::min_element(offsets_.begin(), offsets_.end());
  return static_cast<std::int64_t>(device_ns) + offset_;
}

}  // namespace underwater_stereo
