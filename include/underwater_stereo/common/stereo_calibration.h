// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Calibration of one camera and of a stereo pair, with the fields and meaning of
/// sensor_msgs/CameraInfo (plumb_bob distortion), so it converts to and from camera_info losslessly.

#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace underwater_stereo {

/// Calibration of one camera of a rectified stereo pair, as sensor_msgs/CameraInfo holds it.
struct CameraCalibration {
  int width = 0;                          ///< [px] image width the calibration belongs to
  int height = 0;                         ///< [px]
  cv::Matx33d K = cv::Matx33d::zeros();   ///< intrinsic matrix of the raw (distorted) image
  std::vector<double> D;                  ///< plumb_bob distortion k1, k2, p1, p2, k3 (may be empty: none)
  cv::Matx33d R = cv::Matx33d::eye();     ///< rotation from the raw camera frame to the rectified frame
  cv::Matx34d P = cv::Matx34d::zeros();   ///< projection of the rectified camera; P(0,3) = -fx * baseline on the right

  /// Every problem that makes this calibration unusable (zero focal length, NaN, size...). Empty when valid.
  std::vector<std::string> validate(const std::string& name) const;
};

/// Calibration of the stereo head: both cameras rectified to a common image plane.
struct StereoCalibration {
  CameraCalibration left;
  CameraCalibration right;

  /// [px] focal length of the rectified pair, P(0,0) of the left camera.
  double focalPx() const { return left.P(0, 0); }
  /// [m] distance between the rectified optical centres, -P_right(0,3) / P_right(0,0).
  double baselineM() const { return -right.P(0, 3) / right.P(0, 0); }
  /// [px] disparity of a point at depth z_m in front of the rectified left camera.
  double disparityAtDepth(double z_m) const { return focalPx() * baselineM() / z_m; }

  /// Every problem of both cameras plus the pair (sizes differ, left P(0,3) != 0, baseline <= 0...).
  std::vector<std::string> validate() const;
};

}  // namespace underwater_stereo
