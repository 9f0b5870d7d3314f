// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Step 2 of the pipeline: masks of the designated colours (HSV inRange, then opening and closing).

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace underwater_stereo {

/// A designated colour class, in OpenCV HSV units (H 0-179, S and V 0-255).
/// hue_min > hue_max means the range wraps through 0 (red: e.g. 170..10).
struct ColourClass {
  std::string name;
  int hue_min = 0;
  int hue_max = 179;
  int saturation_min = 80;
  int saturation_max = 255;
  int value_min = 40;
  int value_max = 255;
};

struct ColourMaskConfig {
  std::vector<ColourClass> classes;  ///< the designated colours, at least one
  /// Grey-world white balance before HSV: scales B, G, R so their means are equal, undoing the water's
  /// colour cast (red is lost fastest). Off reproduces the paper.
  bool grey_world = true;
  int open_kernel_px = 10;           ///< opening removes specks smaller than this (paper: 10x10); 0 or 1 = off
  int close_kernel_px = 10;          ///< closing fills holes smaller than this (paper: 10x10); 0 or 1 = off

  std::vector<std::string> validate() const;
};

/// Grey-world white balance of a BGR8 image. @throw std::invalid_argument when not CV_8UC3 or empty.
cv::Mat greyWorld(const cv::Mat& bgr);

/// One binary mask (CV_8UC1, 0/255) per colour class, in class order, after opening and closing.
/// `bgr` is the frame as searched (after any white balance). @throw std::invalid_argument when `bgr`
/// is empty or not CV_8UC3.
std::vector<cv::Mat> colourMasks(const cv::Mat& bgr, const ColourMaskConfig& config);

}  // namespace underwater_stereo
