// SPDX-License-Identifier: BSD-3-Clause
// Shape fitting on synthetic stereo-like points (visible face only, noise) with exact outline rays.
#include <gtest/gtest.h>

#include <random>

#include "underwater_stereo/detection/shape_fitter.h"

using namespace underwater_stereo;

namespace {

constexpr unsigned kSeed = 7;

std::vector<Eigen::Vector3f> visibleSphere(const Eigen::Vector3d& c, double r, double noise, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Eigen::Vector3f> pts;
  while (pts.size() < 1500) {
    const Eigen::Vector3d dir = Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    const Eigen::Vector3d p = c + r * dir;
    if (dir.dot(-p.normalized()) < 0.15) continue;  // only the face towards the camera
    pts.push_back((p + p.normalized() * noise * n(rng)).cast<float>());
  }
  return pts;
}

std::vector<Eigen::Vector3d> sphereOutline(const Eigen::Vector3d& c, double r) {
  const double d = c.norm();
  const Eigen::Vector3d w = c / d, a = w.unitOrthogonal(), b = w.cross(a);
  std::vector<Eigen::Vector3d> rays;
  for (int i = 0; i < 360; ++i) {
    const double t = 2 * M_PI * i / 360;
    rays.push_back((c - (r * r / d) * w + r * std::sqrt(1 - r * r / (d * d)) * (std::cos(t) * a + std::sin(t) * b))
                       .normalized());
  }
  return rays;
}

}  // namespace

TEST(ShapeFitter, SphereFromItsVisibleCapAndSilhouette) {
  std::mt19937 rng(kSeed);
  const Eigen::Vector3d c(0.3, -0.1, 2.5);
  const auto fit = fitShape(visibleSphere(c, 0.15, 0.01, rng), sphereOutline(c, 0.15), {OutlineKind::kCircle}, ShapeFitConfig{});
  EXPECT_EQ(fit.shape, ShapeKind::kSphere) << "seed " << kSeed;
  EXPECT_LT((fit.centre - c).norm(), 0.01);
  EXPECT_NEAR(fit.size.x(), 0.30, 0.01);
  EXPECT_LT(fit.rmse_m, 0.011);  // noise along the ray, seen across the surface
  EXPECT_GT(fit.rmse_m, 0.003);
}

TEST(ShapeFitter, TiltedPanelIsAPlaneWithItsOutlineSize) {
  std::mt19937 rng(kSeed);
  std::normal_distribution<double> n(0.0, 0.004);
  const Eigen::Vector3d c(0.2, 0.1, 3.0);
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()).toRotationMatrix();
  std::vector<Eigen::Vector3f> pts;
  for (double u = -0.22; u <= 0.22; u += 0.01) {
    for (double v = -0.17; v <= 0.17; v += 0.01) pts.push_back((c + rot * Eigen::Vector3d(u, v, n(rng))).cast<float>());
  }
  std::vector<Eigen::Vector3d> rays;
  for (int i = 0; i < 100; ++i) {
    const double t = -1 + 2 * i / 99.0;
    for (const Eigen::Vector3d& local : {Eigen::Vector3d(0.25 * t, -0.2, 0), Eigen::Vector3d(0.25 * t, 0.2, 0),
                                         Eigen::Vector3d(-0.25, 0.2 * t, 0), Eigen::Vector3d(0.25, 0.2 * t, 0)}) {
      rays.push_back((c + rot * local).normalized());
    }
  }
  const auto fit = fitShape(pts, rays, {OutlineKind::kRectangle}, ShapeFitConfig{});
  ASSERT_EQ(fit.shape, ShapeKind::kPlane) << "seed " << kSeed;
  EXPECT_LT((fit.centre - c).norm(), 0.02);
  EXPECT_NEAR(std::max(fit.size.x(), fit.size.y()), 0.5, 0.015);
  EXPECT_NEAR(std::min(fit.size.x(), fit.size.y()), 0.4, 0.015);
  const Eigen::Vector3d normal = fit.orientation * Eigen::Vector3d::UnitZ();
  EXPECT_GT(std::abs(normal.dot(rot * Eigen::Vector3d::UnitZ())), 0.99);
}

TEST(ShapeFitter, TubeIsACylinderAlongItsAxis) {
  std::mt19937 rng(kSeed);
  std::normal_distribution<double> n(0.0, 0.003);
  std::uniform_real_distribution<double> along(-0.4, 0.4), angle(-M_PI / 2 + 0.2, M_PI / 2 - 0.2);
  const Eigen::Vector3d c(0.0, 0.2, 2.0);
  const double r = 0.05;
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 1500; ++i) {
    const double a = angle(rng);  // facing the camera: -z side of the axis
    pts.push_back((c + Eigen::Vector3d(along(rng), r * std::sin(a), -r * std::cos(a)) + Eigen::Vector3d::Constant(n(rng)))
                      .cast<float>());
  }
  std::vector<Eigen::Vector3d> rays;
  for (int i = 0; i <= 100; ++i) {
    const double x = -0.4 + 0.8 * i / 100.0;
    rays.push_back((c + Eigen::Vector3d(x, -r, 0)).normalized());
    rays.push_back((c + Eigen::Vector3d(x, r, 0)).normalized());
  }
  const auto fit = fitShape(pts, rays, {OutlineKind::kRectangle}, ShapeFitConfig{});
  ASSERT_EQ(fit.shape, ShapeKind::kCylinder) << "seed " << kSeed;
  EXPECT_NEAR(fit.size.z(), 0.8, 0.03);
  EXPECT_NEAR(fit.size.x(), 0.1, 0.01);
  EXPECT_LT((fit.centre - c).norm(), 0.02);
  const Eigen::Vector3d axis = fit.orientation * Eigen::Vector3d::UnitZ();
  EXPECT_GT(std::abs(axis.x()), 0.99);
}

TEST(ShapeFitter, FlatFacesOfDifferentShadingMakeABoxAlongThePointsAxes) {
  // Two visible faces of a 0.4 x 0.3 x 0.2 box at 3 m, turned 35 degrees about y, with 5 mm noise.
  std::mt19937 rng(kSeed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::normal_distribution<double> n(0.0, 0.005);
  const Eigen::Matrix3d r = Eigen::AngleAxisd(35 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d c(0.2, 0.1, 3.0), half(0.2, 0.15, 0.1);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 3000; ++i) {
    Eigen::Vector3d local(2 * half.x() * u(rng), 2 * half.y() * u(rng), 2 * half.z() * u(rng));
    if (i % 2) local.z() = -half.z();  // the face towards the camera...
    else local.x() = -half.x();        // ...and the side face
    pts.push_back((c + r * local + Eigen::Vector3d(n(rng), n(rng), n(rng))).cast<float>());
  }
  const auto rays = sphereOutline(c, 0.25);
  EXPECT_NE(fitShape(pts, rays, {OutlineKind::kEllipse, 5.0}, ShapeFitConfig{}).shape, ShapeKind::kBox) << "smooth shading";
  const auto fit = fitShape(pts, rays, {OutlineKind::kEllipse, 75.0}, ShapeFitConfig{});
  ASSERT_EQ(fit.shape, ShapeKind::kBox);
  std::vector<double> size{fit.size.x(), fit.size.y(), fit.size.z()};
  std::sort(size.begin(), size.end());
  EXPECT_NEAR(size[2], 0.4, 0.03);
  EXPECT_NEAR(size[1], 0.3, 0.03);
  // Only two faces are seen: the third extent and the centre are as far as the visible faces reach.
  EXPECT_NEAR(size[0], 0.2, 0.03);
  EXPECT_LT((fit.centre - c).norm(), 0.03);
}

TEST(ShapeFitter, TooFewPointsIsUnknownWithTheirCentroid) {
  const std::vector<Eigen::Vector3f> pts{{0, 0, 2}, {0.1F, 0, 2}, {0, 0.1F, 2}};
  const auto fit = fitShape(pts, sphereOutline({0, 0, 2}, 0.1), {OutlineKind::kCircle}, ShapeFitConfig{});
  EXPECT_EQ(fit.shape, ShapeKind::kUnknown);
  EXPECT_NEAR(fit.centre.z(), 2.0, 1e-6);
  EXPECT_NEAR(fit.size.x(), 0.1, 1e-6);
  EXPECT_EQ(fitShape({}, {}, {OutlineKind::kCircle}, ShapeFitConfig{}).shape, ShapeKind::kUnknown);
}

TEST(ShapeFitter, InvalidConfigIsReported) {
  EXPECT_TRUE(ShapeFitConfig{}.validate().empty());
  ShapeFitConfig bad;
  bad.min_points = 1;
  bad.plane_preference = 0.5;
  bad.min_elongation = 0.5;
  bad.box_face_contrast = 0;
  EXPECT_EQ(bad.validate().size(), 4U);
}
