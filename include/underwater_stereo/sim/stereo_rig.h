// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The simulated stereo head's true geometry, and the calibration a perfect in-water calibration would give.

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "underwater_stereo/common/stereo_calibration.h"
#include "underwater_stereo/sim/scene.h"

namespace underwater_stereo {
namespace sim {

/// One raw (unrectified) pinhole camera with plumb_bob distortion.
struct PinholeCamera {
  int width = 0;
  int height = 0;
  cv::Matx33d K = cv::Matx33d::eye();
  std::vector<double> D;  ///< k1 k2 p1 p2 k3
};

/// True geometry of the head: both cameras and the right camera's pose in the left optical frame.
class StereoRig {
 public:
  explicit StereoRig(const RigConfig& config);

  const PinholeCamera& left() const { return left_; }
  const PinholeCamera& right() const { return right_; }
  /// Pose of the right camera's optical frame in the left optical frame (x_left = T * x_right).
  const Eigen::Isometry3d& rightInLeft() const { return right_in_left_; }
  /// Calibration with rectification (cv::stereoRectify, zero disparity at infinity), as camera_info carries it.
  const StereoCalibration& calibration() const { return calibration_; }

 private:
  PinholeCamera left_;
  PinholeCamera right_;
  Eigen::Isometry3d right_in_left_;
  StereoCalibration calibration_;
};

/// Rotation from roll/pitch/yaw in degrees (applied x, then y, then z: R = Rz * Ry * Rx).
Eigen::Matrix3d rotationFromRpyDeg(const Eigen::Vector3d& rpy_deg);

}  // namespace sim
}  // namespace underwater_stereo
