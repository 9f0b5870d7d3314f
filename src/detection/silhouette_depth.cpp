// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/silhouette_depth.h"

#include <Eigen/Geometry>

#include <cmath>

namespace underwater_stereo {

bool placeAtSilhouetteDepth(ShapeFit& fit, double disparity, const StereoCalibration& calibration, bool cut_by_border) {
  if (!std::isfinite(disparity) || disparity <= 0 || fit.shape == ShapeKind::kUnknown) return false;
  const Eigen::Matrix3d r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(calibration.left.R.val);
  const double z_rectified = (r * fit.centre).z();
  if (z_rectified <= 0) return false;
  double z_target = calibration.focalPx() * calibration.baselineM() / disparity + fit.hidden_depth_m;
  if (fit.shape == ShapeKind::kSphere || fit.shape == ShapeKind::kCylinder) {
    // The silhouette's shift is its column profile's centroid's: a mean of the outline's own shifts in which each
    // piece counts by its horizontal distance from the centroid times its height. A sphere's outline is its
    // tangent circle, R^2 / d in front of its centre (d: centre distance); a tube's sides are its tangent lines,
    // as far in front of its axis, and count by sin^2 of the axis' angle to the image rows.
    const double at_silhouette = z_target / z_rectified;
    const double radius = fit.size.x() / 2 * at_silhouette, d = fit.centre.norm() * at_silhouette;
    const double tangent = z_target * (1 / (1 - radius * radius / (d * d)) - 1);
    double in_front = tangent;
    if (fit.shape == ShapeKind::kCylinder && !cut_by_border) {
      // Its ends count by cos^2. An end whose cap faces away from the camera shows the near half of its rim,
      // pi/4 of a radius (times the axis' share across the view) in front of the axis on average; a cap facing
      // the camera shows its far half, the two ends balance about the axis, and the tube is taken as its sides
      // (R^2 / d: the difference is below that). Neither cap faces the camera when the centre lies within half
      // the length of the plane through the camera across the axis. A tube cut by the border has at most one end
      // in view: taken as its sides too.
      const Eigen::Vector3d axis = r * (fit.orientation * Eigen::Vector3d::UnitZ());
      const double in_image = std::hypot(axis.x(), axis.y());
      const bool caps_face_away = std::abs((r * fit.centre).dot(axis)) < fit.size.z() / 2;
      if (caps_face_away && in_image > 1e-6) {
        const double ends = axis.x() * axis.x() / (in_image * in_image);
        in_front = (1 - ends) * tangent + ends * M_PI / 4 * radius * in_image;
      }
    }
    z_target += in_front;
  }
  if (std::abs(z_target - z_rectified) > kMaxSilhouetteShiftInExtents * fit.size.maxCoeff()) return false;
  const double scale = z_target / z_rectified;
  fit.centre *= scale;
  fit.size *= scale;
  return true;
}

}  // namespace underwater_stereo
