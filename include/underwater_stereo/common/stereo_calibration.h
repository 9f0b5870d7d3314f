// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Calibration of one camera and of a stereo pair, with the fields and meaning of
/// sensor_msgs/CameraInfo (plumb_bob or rational_polynomial distortion), so it converts to and from
/// camera_info losslessly, and the plausibility limits validate() holds it to.

#include <opencv2/core.hpp>

#include <optional>
#include <string>
#include <vector>

namespace underwater_stereo {

/// Limits of a plausible calibration (validate()): beyond them a camera_info is a mistake, not a lens.
constexpr double kMinFocalPx = 50.0;       ///< [px] K and P focal lengths
constexpr double kMaxFocalPx = 20000.0;    ///< [px]
constexpr double kMinBaselineM = 0.01;     ///< [m] stereo baseline
constexpr double kMaxBaselineM = 2.0;      ///< [m]
constexpr double kMaxDistortionCoefficient = 10.0;  ///< |D[i]|

/// The distortion models the rectification (OpenCV's) can undo, with sensor_msgs' names.
enum class DistortionModel { kPlumbBob, kRationalPolynomial };
/// "plumb_bob" or "rational_polynomial".
std::string distortionModelName(DistortionModel model);
/// The model named `name` (sensor_msgs::distortion_models); none for any other (equidistant, empty...).
std::optional<DistortionModel> distortionModelOf(const std::string& name);

/// Calibration of one camera of a rectified stereo pair, as sensor_msgs/CameraInfo holds it.
struct CameraCalibration {
  int width = 0;                          ///< [px] image width the calibration belongs to
  int height = 0;                         ///< [px]
  cv::Matx33d K = cv::Matx33d::zeros();   ///< intrinsic matrix of the raw (distorted) image
  DistortionModel distortion_model = DistortionModel::kPlumbBob;
  /// Distortion k1, k2, p1, p2[, k3] (plumb_bob: 0, 4 or 5 of them; empty: none) or k1, k2, p1, p2, k3,
  /// k4, k5, k6 (rational_polynomial: 8).
  std::vector<double> D;
  cv::Matx33d R = cv::Matx33d::eye();     ///< rotation from the raw camera frame to the rectified frame
  cv::Matx34d P = cv::Matx34d::zeros();   ///< projection of the rectified camera; P(0,3) = -fx * baseline on the right

  /// Every problem that makes this calibration unusable or implausible, each naming `name`, the field and
  /// its allowed range: image size (imageSizeProblem), NaN/Inf, focal lengths outside
  /// [kMinFocalPx, kMaxFocalPx], a principal point outside the image, a K or P that is not a pinhole
  /// matrix, a distortion vector of the wrong length for its model or with |D[i]| > kMaxDistortionCoefficient,
  /// an R that is not a rotation. Empty when valid.
  std::vector<std::string> validate(const std::string& name) const;

  /// Every field equal (a new calibration needs new rectification maps).
  bool operator==(const CameraCalibration& other) const;
  bool operator!=(const CameraCalibration& other) const { return !(*this == other); }
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

  /// Every problem of both cameras plus the pair (sizes differ, left P(0,3) != 0, baseline outside
  /// [kMinBaselineM, kMaxBaselineM], different rectified cameras).
  std::vector<std::string> validate() const;

  bool operator==(const StereoCalibration& other) const { return left == other.left && right == other.right; }
  bool operator!=(const StereoCalibration& other) const { return !(*this == other); }
};

}  // namespace underwater_stereo
