// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Argument checks shared by the pipeline stages and its entry points.

#include <opencv2/core.hpp>

#include <stdexcept>
#include <string>

#include "underwater_stereo/common/image_size.h"

namespace underwater_stereo {

/// @throw std::invalid_argument naming `who` when imageSizeProblem() finds one.
inline void requireImageSize(const cv::Size& size, double search_scale, const char* who) {
  const std::string why = imageSizeProblem(size.width, size.height, search_scale);
  if (!why.empty()) throw std::invalid_argument(std::string(who) + ": " + why);
}

/// @throw std::invalid_argument naming `who` when `image` is empty or not 8-bit 3-channel (BGR).
inline void requireBgr8(const cv::Mat& image, const char* who) {
  if (image.empty()) throw std::invalid_argument(std::string(who) + ": empty image");
  if (image.type() != CV_8UC3) {
    throw std::invalid_argument(std::string(who) + ": needs an 8-bit 3-channel BGR image, got " +
                                std::to_string(image.channels()) + " channel(s) of depth " +
                                std::to_string(image.depth()));
  }
}

}  // namespace underwater_stereo
