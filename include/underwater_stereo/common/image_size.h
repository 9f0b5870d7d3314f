// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The image sizes the pipeline takes (calibrations, frames, files and messages are held to them).

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace underwater_stereo {

/// [px] Smallest image side the pipeline works with (its blurs, morphology and block matching need room).
constexpr int kMinImageSidePx = 32;
/// [px] Smallest side of the image the colours are searched in (the frame scaled by search_scale).
constexpr int kMinSearchSidePx = 16;
/// [px] Largest image side: width * height * 3 channels stays far below 2^31 (OpenCV's int sizes).
constexpr int kMaxImageSidePx = 16384;
/// [px] Most pixels an image may have: 8K UHD (7680 x 4320), 14 times the head's 1920x1200. The pipeline's
/// buffers grow with the area (a 16384 x 16384 frame took 7.7 GB), and a small file can declare any size.
constexpr long long kMaxImagePixels = 7680LL * 4320;

/// [px] Smallest side a frame may have when it is searched at `search_scale` (0.1-1).
inline int minImageSidePx(double search_scale) {
  return std::max(kMinImageSidePx, static_cast<int>(std::ceil(kMinSearchSidePx / search_scale - 1e-9)));
}

/// Why a `width` x `height` image cannot be processed at `search_scale` (a sentence naming the allowed
/// range), or an empty string when it can. Takes 64-bit sizes so that a message's unsigned fields are
/// judged before anything multiplies them.
inline std::string imageSizeProblem(long long width, long long height, double search_scale = 1.0) {
  const int min_side = minImageSidePx(search_scale);
  const bool sides = width >= min_side && height >= min_side && width <= kMaxImageSidePx && height <= kMaxImageSidePx;
  if (sides && width * height <= kMaxImagePixels) return "";
  std::string why = "image size " + std::to_string(width) + "x" + std::to_string(height);
  if (sides) {
    return why + " has " + std::to_string(width * height) + " pixels, more than " + std::to_string(kMaxImagePixels) +
           " (8K UHD)";
  }
  why += " is outside " + std::to_string(min_side) + ".." + std::to_string(kMaxImageSidePx) + " px per side";
  if (min_side > kMinImageSidePx) why += " (search_scale " + cv::format("%g", search_scale) + " needs >= " +
                                          std::to_string(min_side) + ")";
  return why;
}

}  // namespace underwater_stereo
