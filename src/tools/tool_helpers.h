// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Small pieces the command-line tools share.
#include <opencv2/imgproc.hpp>

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

/// A rendered image as the detector takes it: bayer_rggb8 demosaiced as cv_bridge does, bgr8 as it is.
inline cv::Mat toBgr(const cv::Mat& raw, const std::string& encoding) {
  if (encoding != "bayer_rggb8") return raw;
  cv::Mat bgr;
  cv::cvtColor(raw, bgr, cv::COLOR_BayerBG2BGR);
  return bgr;
}

}  // namespace tools
}  // namespace underwater_stereo
