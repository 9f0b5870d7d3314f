// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file CameraCalibration <-> sensor_msgs/CameraInfo.

#include <sensor_msgs/CameraInfo.h>

#include "underwater_stereo/common/stereo_calibration.h"

namespace underwater_stereo {
namespace ros_glue {

/// camera_info of the calibration (header left empty for the caller).
sensor_msgs::CameraInfo toCameraInfo(const CameraCalibration& calibration);
/// Copies the fields; does not validate their values (call CameraCalibration::validate()).
/// @throw std::invalid_argument when distortion_model is neither plumb_bob nor rational_polynomial (an empty
/// one is taken as plumb_bob when D is empty too).
CameraCalibration fromCameraInfo(const sensor_msgs::CameraInfo& info);

}  // namespace ros_glue
}  // namespace underwater_stereo
