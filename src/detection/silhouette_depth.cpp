// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/silhouette_depth.h"

#include <Eigen/Geometry>

#include <cmath>

namespace underwater_stereo {

bool placeAtSilhouetteDepth(ShapeFit& fit, double disparity, const StereoCalibration& calibration) {
  if (!std::isfinite(disparity) || disparity <= 0 || fit.shape == ShapeKind::kUnknown) return false;
  const Eigen::Matrix3d r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(calibration.left.R.val);
  const double z_rectified = (r * fit.centre).z();
  if (z_rectified <= 0) return false;
  double z_target = calibration.focalPx() * calibration.baselineM() / disparity + fit.hidden_depth_m;
  if (fit.shape == ShapeKind::kSphere) {
    // A sphere's outline is its tangent circle, R^2 / d in front of its centre (d: centre distance).
    const double radius = fit.size.x() / 2 * z_target / z_rectified, d = fit.centre.norm() * z_target / z_rectified;
    z_target *= 1 / (1 - radius * radius / (d * d));
  } else if (fit.shape == ShapeKind::kCylinder) {
    // The silhouette's horizontal shift comes from its left and right ends. Along a tube lying across the
    // image those are the end rims nearest the camera (perspective pushes them furthest out), a radius in
    // front of the axis; across a tube standing upright they are its tangent lines, level with the axis.
    const Eigen::Vector3d axis = r * (fit.orientation * Eigen::Vector3d::UnitZ());
    const double in_image = std::hypot(axis.x(), axis.y());
    if (in_image > 1e-6) z_target += fit.size.x() / 2 * std::abs(axis.x()) / in_image;
  }
  if (std::abs(z_target - z_rectified) > kMaxSilhouetteShiftInExtents * fit.size.maxCoeff()) return false;
  const double scale = z_target / z_rectified;
  fit.centre *= scale;
  fit.size *= scale;
  return true;
}

}  // namespace underwater_stereo
