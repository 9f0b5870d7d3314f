// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Reading an image file strictly: a truncated or corrupt file is an error, not a partly grey image.

#include <opencv2/core.hpp>

#include <string>

namespace underwater_stereo {

/// The colour (BGR8) image in the file at `path`, as cv::imread(IMREAD_COLOR) reads an 8-bit one, after checks
/// that OpenCV does not make: a JPEG must decode without any libjpeg warning (a truncated file, "premature end
/// of data", corrupt entropy data) and a PNG must end in its IEND chunk; the size its header declares must
/// lie in imageSizeProblem()'s range before anything is decoded. A 16-bit image is scaled by 1/257, a
/// floating-point one (e.g. TIFF) read as brightness 0..1, clipped (OpenCV's own conversion of those is not linear).
/// An EXIF orientation tag is ignored: the pixels stay in the layout the camera's calibration and a labelling
/// tool's boxes refer to, not turned for viewing.
/// @throw std::invalid_argument naming `path` and what is wrong (cannot open, empty, truncated, corrupt,
/// not an image format OpenCV reads, size out of range, floating point not finite, signed integers).
cv::Mat readImageFile(const std::string& path);

/// True when the three channels of `bgr` are equal everywhere: a grey image, whose colours cannot be told.
bool isGreyImage(const cv::Mat& bgr);

}  // namespace underwater_stereo
