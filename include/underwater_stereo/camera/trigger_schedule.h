// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file When the stereo head sends its software triggers: ticks on the wall clock.

#include <cstdint>

namespace underwater_stereo {

/// Software-trigger instants for a rate: mid-way between the multiples of the period since the Unix epoch, on
/// the wall clock, the period in whole microseconds (15 Hz: 66 667 us). Both camera threads compute the same
/// ticks, so a pair's two triggers go out together; ticks tied to the wall clock are the same in every process
/// of the host, and on every host whose clock is synchronised (NTP, PTP), so other sensors can be triggered in
/// step. A camera that exposes when triggered does not care about the phase; Aravis' fake camera serves triggers
/// only at the multiples of its own period on the same clock, so its trigger is best sent half a period off them.
class TriggerSchedule {
 public:
  /// `rate_hz` > 0 (a throw otherwise).
  explicit TriggerSchedule(double rate_hz);

  std::int64_t periodUs() const { return period_us_; }

  /// The first tick strictly after `now_us` (wall clock, microseconds since the epoch; negative allowed).
  std::int64_t nextAfter(std::int64_t now_us) const;

  /// The tick to wait for, given the one waited for so far: `tick_us` while it is still ahead and no more than a
  /// period away; otherwise (the wall clock was stepped back, or the tick has passed) the next after `now_us`.
  std::int64_t keepOrRenew(std::int64_t tick_us, std::int64_t now_us) const;

 private:
  std::int64_t period_us_;
};

}  // namespace underwater_stereo
