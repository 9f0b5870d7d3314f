// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Semi-global block matching over three paths (left-to-right, right-to-left, top-down), giving the same
/// disparities as OpenCV 4's cv::StereoSGBM in MODE_SGBM_3WAY, bit for bit, in less than half its time.
///
/// Debian's OpenCV is built for SSE2 only, and its 3WAY matcher runs 8 disparities per instruction. This one runs
/// the same arithmetic (Birchfield-Tomasi pixel costs on the clipped horizontal Sobel and on the raw grey, block
/// sums, the three paths' saturating 16-bit recurrences, uniqueness, parabolic sub-pixel refinement, the one-map
/// left-right check, OpenCV's four row stripes and its 3x3 median) 16 disparities at a time with AVX2, and breaks
/// ties between equal costs the way OpenCV's 8-lane search does. Without AVX2 it calls cv::StereoSGBM itself: on
/// every CPU other than x86-64 (the AVX2 code is compiled for x86-64 only), on x86-64 CPUs without AVX2, and when
/// the environment variable UWS_PORTABLE_MATCHER is set (not empty, not "0"), which keeps that path testable.

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace underwater_stereo {

/// The widest search Sgbm3WayMatcher takes (SgbmParams::num_disparities).
constexpr int kMaxSgbmDisparities = 1024;

/// The cv::StereoSGBM settings this matcher supports (minDisparity 0, preFilterCap 0, no speckle filter).
struct SgbmParams {
  int num_disparities = 16;  ///< searched disparities 0..num_disparities-1; a multiple of 16, <= kMaxSgbmDisparities
  int block_size = 5;        ///< odd, 3..11
  int p1 = 200;              ///< penalty for a disparity change of one between neighbours
  int p2 = 800;              ///< penalty for a larger change; > p1
  int uniqueness_ratio = 5;  ///< [%] the best cost must beat every other (beyond +-1) by this much; 0..99
  int disp12_max_diff = 1;   ///< left-right check tolerance [px]; 1 or more

  std::vector<std::string> validate() const;
};

class Sgbm3WayMatcher {
 public:
  /// @throw std::invalid_argument when the parameters do not validate.
  explicit Sgbm3WayMatcher(const SgbmParams& params);

  /// Disparity of every left pixel, CV_16SC1 in 1/16 px, -16 where there is none: exactly what
  /// cv::StereoSGBM::create(0, n, bs, p1, p2, disp12, 0, uniqueness, 0, 0, MODE_SGBM_3WAY)->compute() gives.
  /// Safe to call from several threads at once.
  /// @throw std::invalid_argument unless left and right are CV_8UC1 of one size wider than num_disparities.
  cv::Mat compute(const cv::Mat& left, const cv::Mat& right) const;

  /// Environment variable that, set to anything but "" or "0", switches the AVX2 matcher off (read once per process).
  static constexpr const char* kPortableMatcherEnv = "UWS_PORTABLE_MATCHER";

  /// Whether compute() runs the AVX2 matcher: built for x86-64, this CPU has AVX2 and UWS_PORTABLE_MATCHER is not
  /// set (otherwise compute() calls OpenCV's).
  static bool accelerated();

 private:
  SgbmParams params_;
};

}  // namespace underwater_stereo
