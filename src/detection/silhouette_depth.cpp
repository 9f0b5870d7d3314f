// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/silhouette_depth.h"

#include <Eigen/Core>

#include <cmath>

namespace underwater_stereo {

bool placeAtSilhouetteDepth(ShapeFit& fit, double disparity, const StereoCalibration& calibration) {
  if (!std::isfinite(disparity) || disparity <= 0 || fit.shape == ShapeKind::kUnknown) return false;
  const Eigen::Matrix3d r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(calibration.left.R.val);
  const double z_rectified = (r * fit.centre).z();
  if (z_rectified <= 0) return false;
  double z_target = calibration.focalPx() * calibration.baselineM() / disparity + fit.hidden_depth_m;
  if (fit.shape == ShapeKind::kSphere || fit.shape == ShapeKind::kCylinder) {
    // A sphere's outline is its tangent circle, R^2 / d in front of its centre (d: centre distance); a tube's
    // sides are its tangent lines, as far in front of its axis. Its ends' rims lie up to a radius nearer, but
    // the fit's axis and radius are least sure exactly there (docs/accuracy.md, "A tube's silhouette").
    const double radius = fit.size.x() / 2 * z_target / z_rectified, d = fit.centre.norm() * z_target / z_rectified;
    z_target *= 1 / (1 - radius * radius / (d * d));
  }
  if (std::abs(z_target - z_rectified) > kMaxSilhouetteShiftInExtents * fit.size.maxCoeff()) return false;
  const double scale = z_target / z_rectified;
  fit.centre *= scale;
  fit.size *= scale;
  return true;
}

}  // namespace underwater_stereo
