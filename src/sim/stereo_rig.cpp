// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/sim/stereo_rig.h"

#include <opencv2/calib3d.hpp>

namespace underwater_stereo {
namespace sim {

Eigen::Matrix3d rotationFromRpyDeg(const Eigen::Vector3d& rpy_deg) {
  const Eigen::Vector3d r = rpy_deg * M_PI / 180.0;
  return (Eigen::AngleAxisd(r.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(r.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

StereoRig::StereoRig(const RigConfig& config) {
  const double f = config.focalPx();
  const double cx = (config.width - 1) / 2.0;
  const double cy = (config.height - 1) / 2.0;
  const double off = config.principal_offset_px;
  left_ = {config.width, config.height, cv::Matx33d(f, 0, cx + off, 0, f, cy - off, 0, 0, 1), config.left_distortion};
  // The two lenses differ slightly, as real ones do.
  right_ = {config.width, config.height, cv::Matx33d(f * 1.002, 0, cx - off, 0, f * 1.002, cy + off, 0, 0, 1),
            config.right_distortion};

  right_in_left_ = Eigen::Isometry3d::Identity();
  right_in_left_.linear() = rotationFromRpyDeg(config.right_rotation_deg);
  right_in_left_.translation() = Eigen::Vector3d(config.baseline_m, 0, 0) + config.right_offset_m;

  // stereoRectify wants the transform taking left-frame points into the right frame.
  const Eigen::Isometry3d left_to_right = right_in_left_.inverse();
  cv::Matx33d R;
  cv::Vec3d T;
  for (int i = 0; i < 3; ++i) {
    T[i] = left_to_right.translation()[i];
    for (int j = 0; j < 3; ++j) R(i, j) = left_to_right.linear()(i, j);
  }
  cv::Mat R1, R2, P1, P2, Q;
  const cv::Size size(config.width, config.height);
  cv::stereoRectify(cv::Mat(left_.K), cv::Mat(left_.D), cv::Mat(right_.K), cv::Mat(right_.D), size, cv::Mat(R),
                    cv::Mat(T), R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 0.0, size);
  auto fill = [&](const PinholeCamera& cam, const cv::Mat& Rr, const cv::Mat& Pr, CameraCalibration& out) {
    out.width = cam.width;
    out.height = cam.height;
    out.K = cam.K;
    out.D = cam.D;
    out.R = cv::Matx33d(Rr);
    out.P = cv::Matx34d(Pr);
  };
  fill(left_, R1, P1, calibration_.left);
  fill(right_, R2, P2, calibration_.right);
}

}  // namespace sim
}  // namespace underwater_stereo
