// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/common/stereo_calibration.h"

#include <cmath>

#include "underwater_stereo/common/image_size.h"

namespace underwater_stereo {
namespace {

template <int M, int N>
bool allFinite(const cv::Matx<double, M, N>& m) {
  for (int i = 0; i < M * N; ++i) {
    if (!std::isfinite(m.val[i])) return false;
  }
  return true;
}

std::string number(double v) { return cv::format("%g", v); }

/// The pinhole part (fx, fy, cx, cy and the fixed zeros and one) of K or of P's left 3x3.
void checkPinhole(const std::string& name, const std::string& matrix, double fx, double skew, double cx, double zero1,
                  double fy, double cy, double zero2, double zero3, double one, int width, int height,
                  std::vector<std::string>& problems) {
  for (const auto& [field, f] : {std::pair<const char*, double>{"[0] (fx)", fx}, {"[4] (fy)", fy}}) {
    if (!(f >= kMinFocalPx && f <= kMaxFocalPx)) {
      problems.push_back(name + ": " + matrix + field + " = " + number(f) + " px is outside " + number(kMinFocalPx) +
                         ".." + number(kMaxFocalPx) + (f == 0.0 ? " (camera not calibrated)" : ""));
    }
  }
  // Against fx only when fx itself is sound: a NaN or zero fx is named above, not a second time as a skew problem.
  const bool fx_sound = fx >= kMinFocalPx && fx <= kMaxFocalPx;
  if (!std::isfinite(skew) || (fx_sound && !(std::abs(skew) <= 0.1 * fx))) {
    problems.push_back(name + ": " + matrix + " skew " + number(skew) + " exceeds 0.1 * fx");
  }
  if (!(cx >= 0 && cx <= width)) {
    problems.push_back(name + ": " + matrix + " principal point cx = " + number(cx) + " is outside the image (0.." +
                       std::to_string(width) + ")");
  }
  if (!(cy >= 0 && cy <= height)) {
    problems.push_back(name + ": " + matrix + " principal point cy = " + number(cy) + " is outside the image (0.." +
                       std::to_string(height) + ")");
  }
  if (zero1 != 0.0 || zero2 != 0.0 || zero3 != 0.0 || one != 1.0) {
    problems.push_back(name + ": " + matrix + " is not a pinhole matrix (row 2 must be 0 0 1, element [3] 0)");
  }
}

}  // namespace

std::string distortionModelName(DistortionModel model) {
  return model == DistortionModel::kRationalPolynomial ? "rational_polynomial" : "plumb_bob";
}

std::optional<DistortionModel> distortionModelOf(const std::string& name) {
  if (name == "plumb_bob") return DistortionModel::kPlumbBob;
  if (name == "rational_polynomial") return DistortionModel::kRationalPolynomial;
  return std::nullopt;
}

std::vector<std::string> CameraCalibration::validate(const std::string& name) const {
  std::vector<std::string> problems;
  const std::string size_problem = imageSizeProblem(width, height);
  if (!size_problem.empty()) problems.push_back(name + ": calibrated " + size_problem);
  if (!allFinite(K) || !allFinite(R) || !allFinite(P)) problems.push_back(name + ": K, R or P contains NaN/Inf");
  checkPinhole(name, "K", K(0, 0), K(0, 1), K(0, 2), K(1, 0), K(1, 1), K(1, 2), K(2, 0), K(2, 1), K(2, 2), width,
               height, problems);
  checkPinhole(name, "P", P(0, 0), P(0, 1), P(0, 2), P(1, 0), P(1, 1), P(1, 2), P(2, 0), P(2, 1), P(2, 2), width,
               height, problems);
  if (P(1, 3) != 0.0 || P(2, 3) != 0.0) {
    problems.push_back(name + ": P[7] and P[11] must be 0 (rectified cameras side by side), are " + number(P(1, 3)) +
                       " and " + number(P(2, 3)));
  }
  for (double d : D) {
    if (!std::isfinite(d)) {
      problems.push_back(name + ": D contains NaN/Inf");
      break;
    }
    if (std::abs(d) > kMaxDistortionCoefficient) {
      problems.push_back(name + ": distortion coefficient " + number(d) + " is outside -" +
                         number(kMaxDistortionCoefficient) + ".." + number(kMaxDistortionCoefficient));
      break;
    }
  }
  const bool d_fits = distortion_model == DistortionModel::kRationalPolynomial
                          ? (D.empty() || D.size() == 8)
                          : (D.empty() || D.size() == 4 || D.size() == 5 || D.size() == 8);
  if (!d_fits) {
    problems.push_back(name + ": D has " + std::to_string(D.size()) + " coefficients (" +
                       distortionModelName(distortion_model) +
                       (distortion_model == DistortionModel::kRationalPolynomial ? " needs 8 or none)"
                                                                                  : " needs 5, 4 or none)"));
  }
  if (allFinite(R) && cv::norm(R * R.t() - cv::Matx33d::eye()) > 1e-3) {
    problems.push_back(name + ": R is not a rotation matrix");
  } else if (allFinite(R) && cv::determinant(R) < 0) {
    problems.push_back(name + ": R is a reflection (determinant -1), not a rotation");
  }
  return problems;
}

bool CameraCalibration::operator==(const CameraCalibration& o) const {
  return width == o.width && height == o.height && K == o.K && distortion_model == o.distortion_model && D == o.D &&
         R == o.R && P == o.P;
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
  if (left.P(0, 3) != 0.0) problems.push_back("left P[3] must be 0 in a stereo pair, is " + number(left.P(0, 3)));
  if (!(baselineM() > 0.0)) {
    problems.push_back("right P[3] = " + number(right.P(0, 3)) +
                       " gives no positive baseline (expected -fx * baseline)");
  } else if (!(baselineM() >= kMinBaselineM && baselineM() <= kMaxBaselineM)) {
    problems.push_back("baseline -P_right[3] / P_right[0] = " + number(baselineM()) + " m is outside " +
                       number(kMinBaselineM) + ".." + number(kMaxBaselineM) + " m");
  }
  if (std::abs(left.P(0, 0) - right.P(0, 0)) > 1e-6 * left.P(0, 0) ||
      std::abs(left.P(1, 2) - right.P(1, 2)) > 1e-3) {
    problems.push_back("left and right P describe different rectified cameras (fx or cy differ)");
  }
  return problems;
}

}  // namespace underwater_stereo
