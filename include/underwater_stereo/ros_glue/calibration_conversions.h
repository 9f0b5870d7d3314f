// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file CameraCalibration <-> sensor_msgs/CameraInfo.

#include <sensor_msgs/CameraInfo.h>

#include "underwater_stereo/common/stereo_calibration.h"

namespace underwater_stereo {
namespace ros_glue {

/// camera_info with distortion_model plumb_bob (header left empty for the caller).
sensor_msgs::CameraInfo toCameraInfo(const CameraCalibration& calibration);
/// Copies the fields; does not validate (call CameraCalibration::validate()).
CameraCalibration fromCameraInfo(const sensor_msgs::CameraInfo& info);

}  // namespace ros_glue
}  // namespace underwater_stereo
