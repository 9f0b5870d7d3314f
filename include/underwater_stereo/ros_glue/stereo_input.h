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
/// difference (0 for exactly synchronised input).
/// @throw std::invalid_argument naming the topic and the offending value: an encoding not accepted, an empty
/// image, left/right sizes that differ, an image whose size is not its camera_info's, an uncalibrated or
/// non-finite camera_info, stamps further apart than max_skew_s.
StereoInput toStereoInput(const sensor_msgs::Image& left, const sensor_msgs::CameraInfo& left_info,
                          const sensor_msgs::Image& right, const sensor_msgs::CameraInfo& right_info,
                          const std::string& left_topic, const std::string& right_topic, double max_skew_s);

}  // namespace ros_glue
}  // namespace underwater_stereo
