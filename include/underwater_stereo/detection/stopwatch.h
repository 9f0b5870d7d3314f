// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Wall-clock laps for the per-stage timings the detector reports.

#include <chrono>

namespace underwater_stereo {

class Stopwatch {
 public:
  /// Milliseconds since construction or the previous lap.
  double lapMs() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace underwater_stereo
