// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A received stereo pair (images + camera_info) checked and converted for the detector.

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <opencv2/core.hpp>

#include <string>

#include "underwater_stereo/detection/raw_frame.h"
#include "underwater_stereo/common/stereo_calibration.h"

namespace underwater_stereo {
namespace ros_glue {

struct StereoInput {
  /// As received (rgb8 converted to BGR): the messages' buffers are shared, not copied, so keep the
  /// messages while these are used.
  RawFrame left, right;
  StereoCalibration calibration;
};

/// True for the encodings the detector takes: bayer_rggb8/bggr8/gbrg8/grbg8, bgr8, rgb8, mono8.
bool acceptedEncoding(const std::string& encoding);

/// Checks a pair and converts it. `*_topic` name the inputs in messages; `max_skew_s` bounds the stamps'
/// difference (0 for exactly synchronised input); `search_scale` is the detector's (it sets the smallest
/// image size, minImageSidePx()).
/// @throw std::invalid_argument naming the topic, the field and its allowed range: an image size outside
/// minImageSidePx()..kMaxImageSidePx, an encoding not accepted, a step shorter than a row, data not step x
/// height bytes, left/right sizes that differ, an image whose size is not its camera_info's, an unsupported
/// distortion model, binning or a region of interest (not supported), a camera_info that
/// CameraCalibration::validate() refuses, stamps further apart than
/// max_skew_s.
StereoInput toStereoInput(const sensor_msgs::Image& left, const sensor_msgs::CameraInfo& left_info,
                          const sensor_msgs::Image& right, const sensor_msgs::CameraInfo& right_info,
                          const std::string& left_topic, const std::string& right_topic, double max_skew_s,
                          double search_scale = 1.0);

}  // namespace ros_glue
}  // namespace underwater_stereo
