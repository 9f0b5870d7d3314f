// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The left frame with the detections drawn on it, for operators (the paper's "frame with an image of
/// the detected object").

#include <opencv2/core.hpp>

#include "underwater_stereo/detection/detector.h"

namespace underwater_stereo {

/// A copy of `left_bgr` with each detection's contour, box and a label (colour, shape, size, range, XYZ)
/// and the frame's quality status in the top-left corner.
/// @throw std::invalid_argument when `left_bgr` is not a non-empty BGR8 image.
cv::Mat annotate(const cv::Mat& left_bgr, const DetectionResult& result);

}  // namespace underwater_stereo
