// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/tracking/camera_view.h"

#include <cmath>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {

CameraView::CameraView(const CameraCalibration& left, double min_depth_m, double max_depth_m, double margin_px)
    : fx_(left.K(0, 0)),
      fy_(left.K(1, 1)),
      cx_(left.K(0, 2)),
      cy_(left.K(1, 2)),
      width_(left.width),
      height_(left.height),
      min_depth_m_(min_depth_m),
      max_depth_m_(max_depth_m),
      margin_px_(margin_px) {
  std::vector<std::string> problems = left.validate("left camera");
  if (!(min_depth_m >= 0.0 && max_depth_m > min_depth_m)) {
    problems.push_back("workspace depths must satisfy 0 <= min < max (got " + std::to_string(min_depth_m) + ", " +
                       std::to_string(max_depth_m) + ")");
  }
  if (!(margin_px >= 0.0 && 2 * margin_px < std::min(width_, height_))) {
    problems.push_back("view margin must be >= 0 and leave part of the image (got " + std::to_string(margin_px) + ")");
  }
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid camera view", problems));
}

bool CameraView::sees(const Eigen::Vector3d& p) const {
  if (!p.allFinite() || p.z() < min_depth_m_ || p.z() > max_depth_m_) return false;
  const double u = fx_ * p.x() / p.z() + cx_;
  const double v = fy_ * p.y() / p.z() + cy_;
  return u >= margin_px_ && u <= width_ - margin_px_ && v >= margin_px_ && v <= height_ - margin_px_;
}

}  // namespace underwater_stereo
