// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A camera frame as it arrives (BGR, grey or an 8-bit Bayer mosaic), converted only where and as
/// far as the pipeline needs it: the 2D search reads it at half size, stereo reads small regions.

#include <opencv2/core.hpp>

#include <optional>
#include <string>

namespace underwater_stereo {

/// How a frame's pixels are laid out. Bayer layouts are named by their top-left 2x2 cell, row by row
/// (as sensor_msgs' bayer_rggb8 etc.).
enum class PixelLayout { kBgr, kMono, kBayerRggb, kBayerBggr, kBayerGbrg, kBayerGrbg };

/// The layout of a sensor_msgs encoding (bgr8, mono8, bayer_rggb8/bggr8/gbrg8/grbg8); none for any other.
std::optional<PixelLayout> layoutOfEncoding(const std::string& encoding);
/// layoutOfEncoding(), for an encoding that must have one.
/// @throw std::invalid_argument for any other encoding.
PixelLayout pixelLayoutOf(const std::string& encoding);
/// False for grey frames: no designated colour can be named in them (every colour model and the paper's
/// grey_threshold source read colour), so nothing is found.
bool carriesColour(PixelLayout layout);

class RawFrame {
 public:
  RawFrame() = default;
  /// CV_8UC3 is BGR, CV_8UC1 grey: so a cv::Mat converts implicitly.
  /// @throw std::invalid_argument for any other type.
  RawFrame(const cv::Mat& image);  // NOLINT(google-explicit-constructor)
  /// `data` (not copied: keep it unchanged while the frame is used) in `layout`: CV_8UC3 for kBgr, CV_8UC1
  /// otherwise; Bayer frames of even width and height.
  /// @throw std::invalid_argument when type or size do not fit the layout.
  RawFrame(const cv::Mat& data, PixelLayout layout);

  bool empty() const { return data_.empty(); }
  cv::Size size() const { return data_.size(); }
  PixelLayout layout() const { return layout_; }
  const cv::Mat& data() const { return data_; }

  /// BGR8 of `region` (inside the frame; Bayer demosaiced bilinearly, as cv_bridge does, and equal to the
  /// whole frame's demosaicing but for the frame's outermost pixels).
  cv::Mat bgr(const cv::Rect& region) const;
  cv::Mat bgr() const { return bgr(cv::Rect(cv::Point(), size())); }
  /// Grey (BT.601 luma) of `region`.
  cv::Mat grey(const cv::Rect& region) const;
  /// BGR8 of `region` at half size: each 2x2 block averaged; a Bayer cell gives its R and B and its two
  /// G's mean, no demosaicing. `region` must lie on even pixels.
  cv::Mat halfSizeBgr(const cv::Rect& region) const;
  cv::Mat halfSizeBgr() const { return halfSizeBgr(cv::Rect(cv::Point(), size())); }

 private:
  cv::Mat data_;
  PixelLayout layout_ = PixelLayout::kBgr;
};

}  // namespace underwater_stereo
