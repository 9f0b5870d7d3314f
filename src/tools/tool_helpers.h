// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Small pieces the command-line tools share.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace underwater_stereo {
namespace tools {

/// The q-quantile (0..1, nearest rank) of `v`; NaN when empty.
inline double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

}  // namespace tools
}  // namespace underwater_stereo
