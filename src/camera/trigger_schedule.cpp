// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/trigger_schedule.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace underwater_stereo {

TriggerSchedule::TriggerSchedule(double rate_hz) {
  if (!(rate_hz > 0 && rate_hz <= 1e6)) {
    throw std::invalid_argument("TriggerSchedule: rate must be in (0, 1e6] Hz, got " + std::to_string(rate_hz));
  }
  period_us_ = std::max<std::int64_t>(1, std::llround(1e6 / rate_hz));
}

std::int64_t TriggerSchedule::nextAfter(std::int64_t now_us) const {
  const std::int64_t half = period_us_ / 2;
  // Floor division (now may be negative): the last tick at or before now, then one period on.
  std::int64_t k = (now_us - half) / period_us_;
  if ((now_us - half) % period_us_ < 0) --k;
  return (k + 1) * period_us_ + half;
}

std::int64_t TriggerSchedule::keepOrRenew(std::int64_t tick_us, std::int64_t now_us) const {
  return tick_us > now_us && tick_us - now_us <= period_us_ ? tick_us : nextAfter(now_us);
}

}  // namespace underwater_stereo
