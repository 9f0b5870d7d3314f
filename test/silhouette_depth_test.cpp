// SPDX-License-Identifier: BSD-3-Clause
// A fitted object moved to its silhouette's depth, and left where its points put it when the two disagree.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <limits>

#include "sim_test_helpers.h"
#include "underwater_stereo/detection/silhouette_depth.h"
#include "underwater_stereo/sim/renderer.h"

using namespace underwater_stereo;

namespace {

StereoCalibration headCalibration() {
  return sim::Renderer(sim::test::smallScene(sim::test::sphere("ball", {0, 0, 2}, 0.3))).calibration();
}

/// A panel 0.4 m wide whose points put its centre on the rectified axis at `z` [m] (a panel's silhouette lies
/// at its centre's depth: no hidden depth, no tangent correction).
ShapeFit panelAt(double z, const StereoCalibration& c) {
  const Eigen::Matrix3d r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(c.left.R.val);
  ShapeFit fit;
  fit.shape = ShapeKind::kPlane;
  fit.centre = r.transpose() * Eigen::Vector3d(0, 0, z);
  fit.size = Eigen::Vector3d(0.4, 0.3, 0);
  return fit;
}

double rectifiedDepth(const ShapeFit& fit, const StereoCalibration& c) {
  return (Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(c.left.R.val) * fit.centre).z();
}

}  // namespace

// Stereo surfaces are smoothed towards the rim: a silhouette a few centimetres off moves the panel there, its
// angular size kept.
TEST(SilhouetteDepth, MovesAFitToTheDepthItsSilhouetteGives) {
  const StereoCalibration c = headCalibration();
  ShapeFit fit = panelAt(2.0, c);
  ASSERT_TRUE(placeAtSilhouetteDepth(fit, c.disparityAtDepth(2.1), c));
  EXPECT_NEAR(rectifiedDepth(fit, c), 2.1, 1e-9);
  EXPECT_NEAR(fit.size.x(), 0.4 * 2.1 / 2.0, 1e-9);
}

// A silhouette that asks for a move longer than kMaxSilhouetteShiftInExtents of the object's size was matched
// to another outline: the fit stays where its points put it, in either direction.
TEST(SilhouetteDepth, LeavesAFitWhoseSilhouetteDisagreesWithItsPoints) {
  const StereoCalibration c = headCalibration();
  const double limit = kMaxSilhouetteShiftInExtents * 0.4;
  for (const double z : {2.0 + 1.1 * limit, 2.0 - 1.1 * limit, 3.0, 1.2}) {
    ShapeFit fit = panelAt(2.0, c);
    EXPECT_FALSE(placeAtSilhouetteDepth(fit, c.disparityAtDepth(z), c)) << z;
    EXPECT_NEAR(rectifiedDepth(fit, c), 2.0, 1e-9) << z;
    EXPECT_EQ(fit.size.x(), 0.4) << z;
  }
  ShapeFit fit = panelAt(2.0, c);
  EXPECT_TRUE(placeAtSilhouetteDepth(fit, c.disparityAtDepth(2.0 + 0.9 * limit), c));
}

// No silhouette (NaN), a disparity that is no depth, or a fit without a shape: nothing moves.
TEST(SilhouetteDepth, IgnoresMissingSilhouettesAndUnknownShapes) {
  const StereoCalibration c = headCalibration();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN(), kInf = std::numeric_limits<double>::infinity();
  for (const double d : {kNaN, 0.0, -5.0, kInf}) {
    ShapeFit fit = panelAt(2.0, c);
    EXPECT_FALSE(placeAtSilhouetteDepth(fit, d, c)) << d;
    EXPECT_NEAR(rectifiedDepth(fit, c), 2.0, 1e-9);
  }
  ShapeFit unknown = panelAt(2.0, c);
  unknown.shape = ShapeKind::kUnknown;
  EXPECT_FALSE(placeAtSilhouetteDepth(unknown, c.disparityAtDepth(2.1), c));
}

// A tube lying across the view with neither cap facing the camera shows the near halves of its end rims: its axis
// is put pi/4 of a radius behind the silhouette's depth. Slid along its axis until a cap faces the camera, the ends
// balance and only its sides (tangent lines, R^2 / d in front of the axis) count; so too when the border cuts it.
TEST(SilhouetteDepth, ATubesEndsCountOnlyWhenBothCapsFaceAway) {
  const StereoCalibration c = headCalibration();
  const Eigen::Matrix3d r = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(c.left.R.val);
  auto tube = [&](double x) {  // 0.2 m across, 0.6 m long, along the rectified x axis, its centre at depth 2 m
    ShapeFit fit;
    fit.shape = ShapeKind::kCylinder;
    fit.centre = r.transpose() * Eigen::Vector3d(x, 0, 2.0);
    fit.size = Eigen::Vector3d(0.2, 0.2, 0.6);
    fit.orientation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), r.transpose() * Eigen::Vector3d::UnitX());
    return fit;
  };
  const double silhouette = c.disparityAtDepth(1.9);
  ShapeFit ends_away = tube(0.1);  // |centre . axis| = 0.1 < 0.3: both caps face away
  ASSERT_TRUE(placeAtSilhouetteDepth(ends_away, silhouette, c));
  EXPECT_NEAR(rectifiedDepth(ends_away, c), 1.9 + M_PI / 4 * 0.1 * 1.9 / 2.0, 1e-6);
  auto sides_only = [](double x, double z) {
    const double radius = 0.1 * 1.9 / 2.0, d = std::hypot(x, 2.0) * 1.9 / 2.0;
    return z / (1 - radius * radius / (d * d));
  };
  ShapeFit cap_facing = tube(0.5);  // 0.5 > 0.3: the cap at x = 0.2 faces the camera
  ASSERT_TRUE(placeAtSilhouetteDepth(cap_facing, silhouette, c));
  EXPECT_NEAR(rectifiedDepth(cap_facing, c), sides_only(0.5, 1.9), 1e-6);
  ShapeFit cut = tube(0.1);
  ASSERT_TRUE(placeAtSilhouetteDepth(cut, silhouette, c, true));
  EXPECT_NEAR(rectifiedDepth(cut, c), sides_only(0.1, 1.9), 1e-6);
}
