// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Whether the left camera should see a point: the detector's workspace and the image's bounds.

#include <Eigen/Core>

#include "underwater_stereo/common/stereo_calibration.h"

namespace underwater_stereo {

/// The part of space where the detector can find an object: depth within the workspace and the projection
/// (pinhole, raw K; lens distortion is small against the margin) inside the left image by a margin.
class CameraView {
 public:
  /// `min_depth_m`, `max_depth_m`: the detector's workspace (DetectorConfig::stereo); `margin_px`: how far
  /// inside the image an object's centre must project (a half-visible object is often not found).
  /// @throw std::invalid_argument when the calibration does not validate or the bounds are not increasing.
  CameraView(const CameraCalibration& left, double min_depth_m, double max_depth_m, double margin_px);

  /// `p_camera`: [m] in the left optical frame.
  bool sees(const Eigen::Vector3d& p_camera) const;

 private:
  double fx_, fy_, cx_, cy_, width_, height_, min_depth_m_, max_depth_m_, margin_px_;
};

}  // namespace underwater_stereo
