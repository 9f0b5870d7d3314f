// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file How the two cameras of the head share exposure and gain, and the host's auto-exposure law that drives
/// them from the left image. ROS-free.

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace underwater_stereo {

/// independent: each camera as configured (its own ExposureAuto/GainAuto when exposure_us = 0 / gain < 0);
/// master_slave: the host meters the left image inside auto_roi and sets both cameras to the same exposure and
/// gain, so the two images of a pair look alike; fixed: both at exposure_us and gain.
enum class ExposureSync { kIndependent, kMasterSlave, kFixed };

/// "independent", "master_slave" or "fixed". @throw std::invalid_argument for any other name.
ExposureSync exposureSyncFromName(const std::string& name);
std::string exposureSyncName(ExposureSync sync);

/// The metered region as shares of the image (0..1), e.g. {0, 0.25, 1, 0.75}: all but the top quarter, where
/// the bright surface would darken everything below it.
struct AutoRoi {
  double x = 0.0, y = 0.25, width = 1.0, height = 0.75;
};

/// Exposure and gain one frame was (or is to be) taken with.
struct Exposure {
  double exposure_us = 0.0;
  double gain_db = 0.0;
};

struct AutoExposureSettings {
  double target = 0.4;            ///< mean brightness aimed at inside `roi`, share of full scale (0.05..0.95)
  double exposure_min_us = 100.0;
  double exposure_max_us = 20000.0;
  double gain_min_db = 0.0;       ///< gain is raised only once the exposure is at its maximum
  double gain_max_db = 0.0;       ///< = gain_min_db: gain stays where it is
  double deadband = 0.04;         ///< no change while |mean / target - 1| is below this
  double max_step = 2.0;          ///< one update scales exposure x gain by at most this (and at least 1/this)
  AutoRoi roi;

  /// Every problem, each naming the parameter (prefixed with `prefix`, e.g. "~").
  std::vector<std::string> validate(const std::string& prefix) const;
};

/// Mean brightness of an 8-bit image (Mono, Bayer or RGB) inside `roi`, as a share of full scale (0..1). Every
/// 4th pixel in both directions (even strides keep a Bayer mosaic's colours in proportion).
/// @throw std::invalid_argument for an empty image, a depth other than 8 bit, or an ROI outside 0..1 or empty.
double meanBrightness(const cv::Mat& image, const AutoRoi& roi);

/// The next exposure and gain: `measured` (meanBrightness of a frame) was taken with `taken`; the product
/// exposure x linear gain is scaled by target / measured (limited to max_step, nothing inside the deadband),
/// spent on exposure first within its limits, then on gain within its limits. Assumes brightness roughly
/// proportional to exposure x gain; a camera that responds less converges over more frames, never overshoots.
Exposure nextExposure(const AutoExposureSettings& settings, double measured, const Exposure& taken);

}  // namespace underwater_stereo
