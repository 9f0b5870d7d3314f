// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/common/stereo_calibration.h"

#include <cmath>

namespace underwater_stereo {
namespace {

template <int M, int N>
bool allFinite(const cv::Matx<double, M, N>& m) {
  for (int i = 0; i < M * N; ++i) {
    if (!std::isfinite(m.val[i])) return false;
  }
  return true;
}

}  // namespace

std::vector<std::string> CameraCalibration::validate(const std::string& name) const {
  std::vector<std::string> problems;
  if (width <= 0 || height <= 0) {
    problems.push_back(name + ": image size " + std::to_string(width) + "x" + std::to_string(height) +
                       " is not positive");
  }
  if (!allFinite(K) || !allFinite(R) || !allFinite(P)) problems.push_back(name + ": K, R or P contains NaN/Inf");
  for (double d : D) {
    if (!std::isfinite(d)) {
      problems.push_back(name + ": D contains NaN/Inf");
      break;
    }
  }
  if (!(K(0, 0) > 0.0) || !(K(1, 1) > 0.0)) {
    problems.push_back(name + ": K has no focal length (K[0]=" + std::to_string(K(0, 0)) +
                       ", K[4]=" + std::to_string(K(1, 1)) + "): camera is not calibrated");
  }
  if (!(P(0, 0) > 0.0) || !(P(1, 1) > 0.0)) {
    problems.push_back(name + ": P has no focal length (P[0]=" + std::to_string(P(0, 0)) + ")");
  }
  if (!D.empty() && D.size() != 4 && D.size() != 5 && D.size() != 8) {
    problems.push_back(name + ": D has " + std::to_string(D.size()) + " coefficients (plumb_bob needs 5)");
  }
  if (allFinite(R) && cv::norm(R * R.t() - cv::Matx33d::eye()) > 1e-3) {
    problems.push_back(name + ": R is not a rotation matrix");
  }
  return problems;
}

std::vector<std::string> StereoCalibration::validate() const {
  std::vector<std::string> problems = left.validate("left");
  const std::vector<std::string> right_problems = right.validate("right");
  problems.insert(problems.end(), right_problems.begin(), right_problems.end());
  if (!problems.empty()) return problems;
  if (left.width != right.width || left.height != right.height) {
    problems.push_back("left is " + std::to_string(left.width) + "x" + std::to_string(left.height) + " but right is " +
                       std::to_string(right.width) + "x" + std::to_string(right.height));
  }
  if (left.P(0, 3) != 0.0) problems.push_back("left P[3] must be 0 in a stereo pair, is " + std::to_string(left.P(0, 3)));
  if (!(baselineM() > 0.0)) {
    problems.push_back("right P[3] = " + std::to_string(right.P(0, 3)) +
                       " gives no positive baseline (expected -fx * baseline)");
  }
  if (std::abs(left.P(0, 0) - right.P(0, 0)) > 1e-6 * left.P(0, 0) ||
      std::abs(left.P(1, 2) - right.P(1, 2)) > 1e-3) {
    problems.push_back("left and right P describe different rectified cameras (fx or cy differ)");
  }
  return problems;
}

}  // namespace underwater_stereo
