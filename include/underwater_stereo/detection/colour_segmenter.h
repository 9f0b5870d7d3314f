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
  /// Brightness (HSV V) of an object of this colour over that of the water around it, at least; 0 = off.
  /// After white balance any dark object in the water turns reddish (the veiling light in front of it keeps
  /// more red than the far water does), while a red object is brighter than the water: 1.1 for red tells them
  /// apart.
  double min_contrast = 0.0;
  /// [m] an object of this colour measures at least / at most this across its largest side; 0 = no limit.
  double min_size_m = 0.0;
  double max_size_m = 0.0;
  /// With a learnt colour model: its confidence needed for this colour (the share of trees voting for it, or its
  /// boosted trees' score); 0 = colour_model.min_confidence.
  /// learn_colours chooses one per colour by cross-validation (a rare colour needs fewer votes).
  double min_confidence = 0.0;

  /// Whether hue `h` (0-179) lies in [hue_min, hue_max], through 0 when the range wraps.
  bool admitsHue(int h) const { return hue_min <= hue_max ? (h >= hue_min && h <= hue_max) : (h >= hue_min || h <= hue_max); }
  /// Whether the hue range is the whole circle (no hue given: a class only a learnt colour model names).
  bool anyHue() const { return hue_min <= hue_max ? hue_max - hue_min >= 179 : hue_min - hue_max <= 1; }
};

struct ColourMaskConfig {
  std::vector<ColourClass> classes;  ///< the designated colours, at least one
  /// Grey-world white balance before HSV: scales B, G, R so their means are equal, undoing the water's
  /// colour cast (red is lost fastest). Off reproduces the paper.
  bool grey_world = true;
  /// Murky water washes every colour out, and after white balance the water itself is nearly grey. With a
  /// factor > 0 a class's saturation floor drops, in a dull frame, to factor x the frame's median saturation
  /// (the water's; never below saturation_floor_min, never above the class's own floor). 0 = off.
  double saturation_floor_factor = 4.0;
  int saturation_floor_min = 30;
  int blur_px = 5;                   ///< Gaussian blur (kernel size) before HSV against sensor noise in dark frames; 0 or 1 = off
  int open_kernel_px = 10;           ///< opening removes specks smaller than this (paper: 10x10); 0 or 1 = off
  int close_kernel_px = 10;          ///< closing fills holes smaller than this (paper: 10x10); 0 or 1 = off

  std::vector<std::string> validate() const;
};

/// The class named `name` in `classes`, or nullptr when none is.
const ColourClass* findColourClass(const std::vector<ColourClass>& classes, const std::string& name);

/// Per-channel gains that make a BGR8 image's mean grey (grey-world white balance).
/// @throw std::invalid_argument when not CV_8UC3 or empty.
cv::Scalar greyWorldGains(const cv::Mat& bgr);
/// `bgr` with each channel scaled by its gain. @throw std::invalid_argument when not CV_8UC3 or empty.
cv::Mat applyGains(const cv::Mat& bgr, const cv::Scalar& gains);
/// Grey-world white balance of a BGR8 image: applyGains(bgr, greyWorldGains(bgr)).
cv::Mat greyWorld(const cv::Mat& bgr);

/// Where the designated colours are. Binary masks, CV_8UC1 0/255, of the image's size.
struct ColourMasks {
  int saturation_median = 0;     ///< the frame's median HSV saturation (as searched, blurred)
  std::vector<cv::Mat> classes;  ///< one per colour class, in class order: HSV inRange only
  /// The union of all classes after opening then closing: where objects of any designated colour are. The
  /// union is cleaned, not each class, so an object whose shading speckles it between two neighbouring
  /// classes (a yellow ball's shadowed side half orange) stays whole.
  cv::Mat any;
};

/// The masks of `bgr`, the frame as searched (after any white balance). `saturation_median` >= 0 is used
/// instead of measuring it (a part of a frame searched with the whole frame's floors).
/// @throw std::invalid_argument when `bgr` is empty or not CV_8UC3.
ColourMasks colourMasks(const cv::Mat& bgr, const ColourMaskConfig& config, int saturation_median = -1);

}  // namespace underwater_stereo
