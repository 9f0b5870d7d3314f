// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Argument checks shared by the pipeline stages.

#include <opencv2/core.hpp>

#include <stdexcept>
#include <string>

namespace underwater_stereo {

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
