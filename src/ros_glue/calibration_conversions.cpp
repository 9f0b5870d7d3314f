// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/calibration_conversions.h"

#include <stdexcept>

namespace underwater_stereo {
namespace ros_glue {

sensor_msgs::CameraInfo toCameraInfo(const CameraCalibration& c) {
  sensor_msgs::CameraInfo info;
  info.width = static_cast<std::uint32_t>(c.width);
  info.height = static_cast<std::uint32_t>(c.height);
  info.distortion_model = distortionModelName(c.distortion_model);
  info.D = c.D;
  for (int i = 0; i < 9; ++i) {
    info.K[i] = c.K.val[i];
    info.R[i] = c.R.val[i];
  }
  for (int i = 0; i < 12; ++i) info.P[i] = c.P.val[i];
  return info;
}

CameraCalibration fromCameraInfo(const sensor_msgs::CameraInfo& info) {
  CameraCalibration c;
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.D = info.D;
  if (const auto model = distortionModelOf(info.distortion_model)) {
    c.distortion_model = *model;
  } else if (!(info.distortion_model.empty() && info.D.empty())) {  // none given and none needed: no distortion
    throw std::invalid_argument("distortion_model '" + info.distortion_model +
                                "' is not supported (plumb_bob or rational_polynomial)");
  }
  for (int i = 0; i < 9; ++i) {
    c.K.val[i] = info.K[i];
    c.R.val[i] = info.R[i];
  }
  for (int i = 0; i < 12; ++i) c.P.val[i] = info.P[i];
  return c;
}

}  // namespace ros_glue
}  // namespace underwater_stereo
