// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Step 1 of the pipeline: is the frame usable? Mean brightness and dark/bright pixel fractions.

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace underwater_stereo {

enum class QualityStatus { kOk = 0, kTooDark = 1, kTooBright = 2 };  ///< values match ImageQuality.msg

struct QualityConfig {
  /// Mean BT.601 luma (0-255) under which a frame is spoiled (paper: 20; the learnt search still finds a third to a
  /// half of the objects at 10-18: docs/accuracy.md, "Dark and bright frames").
  double too_dark_below = 10.0;
  double too_bright_above = 240.0;   ///< mean luma over which a frame is spoiled (paper: 200; the same section)
  double enhance_below = 40.0;       ///< usable frames darker than this are dark: contrast-normalised (CLAHE on V)
                                     ///< before an HSV search, searched coarser by the learned one
                                     ///< (DetectorConfig::dark_search_width_px)
  int dark_pixel_value = 30;         ///< HSV V (0-255) under which a pixel counts as dark
  int bright_pixel_value = 240;      ///< HSV V over which a pixel counts as bright (saturated)
  double clahe_clip_limit = 3.0;     ///< CLAHE contrast limit
  int clahe_tiles = 8;               ///< CLAHE grid is tiles x tiles

  std::vector<std::string> validate() const;
};

struct QualityReport {
  QualityStatus status = QualityStatus::kOk;
  double mean_brightness = 0.0;   ///< 0-255, mean ITU-R BT.601 luma
  double dark_fraction = 0.0;     ///< 0-1
  double bright_fraction = 0.0;   ///< 0-1
  bool enhanced = false;          ///< the frame needs (and got, from enhanceContrast) normalisation

  bool spoiled() const { return status != QualityStatus::kOk; }
};

/// Measures a BGR8 frame. @throw std::invalid_argument when `bgr` is empty or not CV_8UC3.
QualityReport assessQuality(const cv::Mat& bgr, const QualityConfig& config);

/// Contrast-normalises a dim BGR8 frame: CLAHE on HSV V, hue and saturation kept.
/// @throw std::invalid_argument when `bgr` is empty or not CV_8UC3.
cv::Mat enhanceContrast(const cv::Mat& bgr, const QualityConfig& config);

std::string qualityStatusName(QualityStatus status);

}  // namespace underwater_stereo
