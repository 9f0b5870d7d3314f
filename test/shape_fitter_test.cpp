// SPDX-License-Identifier: BSD-3-Clause
// Shape fitting on synthetic stereo-like points (visible face only, noise) with exact outline rays.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
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

/// Rays of the outline of a `half_u` x `half_v` (half sides) panel centred at `c`, turned by `rot`.
std::vector<Eigen::Vector3d> panelOutline(const Eigen::Vector3d& c, const Eigen::Matrix3d& rot, double half_u, double half_v) {
  std::vector<Eigen::Vector3d> rays;
  for (int i = 0; i < 100; ++i) {
    const double t = -1 + 2 * i / 99.0;
    for (const Eigen::Vector3d& local : {Eigen::Vector3d(half_u * t, -half_v, 0), Eigen::Vector3d(half_u * t, half_v, 0),
                                         Eigen::Vector3d(-half_u, half_v * t, 0), Eigen::Vector3d(half_u, half_v * t, 0)}) {
      rays.push_back((c + rot * local).normalized());
    }
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

TEST(ShapeFitter, ASphereCutByTheImageBorderIsFittedToTheRestOfItsOutline) {
  // A 0.5 m ball 1.2 m away, its right third beyond the image's right edge (x / z > 0.1): the outline runs along
  // the border there. The cone through the rest of the outline is the whole ball's silhouette.
  std::mt19937 rng(kSeed);
  const Eigen::Vector3d c(0.0, 0.05, 1.2);
  const double border = 0.1;
  std::vector<Eigen::Vector3f> pts;
  for (const auto& p : visibleSphere(c, 0.25, 0.005, rng)) {
    if (p.x() / p.z() <= border) pts.push_back(p);
  }
  std::vector<Eigen::Vector3d> rays;
  OutlineCues cues{OutlineKind::kCircle};
  for (const auto& r : sphereOutline(c, 0.25)) {
    const bool cut = r.x() / r.z() > border;
    rays.push_back(cut ? Eigen::Vector3d(border, r.y() / r.z(), 1.0).normalized() : r);
    cues.on_border.push_back(cut);
  }
  const auto fit = fitShape(pts, rays, cues, ShapeFitConfig{});
  ASSERT_EQ(fit.shape, ShapeKind::kSphere);
  EXPECT_LT((fit.centre - c).norm(), 0.02);
  EXPECT_NEAR(fit.size.x(), 0.5, 0.02);
  cues.on_border.clear();  // the border taken for the ball's own edge: the visible part's cone, too small and near
  const auto unaware = fitShape(pts, rays, cues, ShapeFitConfig{});
  EXPECT_LT(unaware.size.x(), 0.45);
  EXPECT_LT(unaware.centre.norm(), c.norm() - 0.02);
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
  const auto fit = fitShape(pts, panelOutline(c, rot, 0.25, 0.2), {OutlineKind::kRectangle}, ShapeFitConfig{});
  ASSERT_EQ(fit.shape, ShapeKind::kPlane) << "seed " << kSeed;
  EXPECT_LT((fit.centre - c).norm(), 0.02);
  EXPECT_NEAR(std::max(fit.size.x(), fit.size.y()), 0.5, 0.015);
  EXPECT_NEAR(std::min(fit.size.x(), fit.size.y()), 0.4, 0.015);
  const Eigen::Vector3d normal = fit.orientation * Eigen::Vector3d::UnitZ();
  EXPECT_GT(std::abs(normal.dot(rot * Eigen::Vector3d::UnitZ())), 0.99);
}

TEST(ShapeFitter, AFarPanelIsAPlaneThoughItsDepthNoiseExceedsItsWidth) {
  // A 0.3 x 0.2 m panel at 4.5 m: stereo's noise of ~1 px of disparity (inverse depth, 0.0045 per m) scatters its
  // points 9 cm along the line of sight, more than its width spreads them, so their least-variance direction lies
  // in the panel and it looked edge-on (no plane fitted). Turned within its own plane too: its sides are measured
  // along its points' longest direction with that noise taken out.
  const Eigen::Vector3d c(-0.3, 0.2, 4.5);
  for (const double turn : {0.0, 0.5, 1.0, 1.57}) {
    std::mt19937 rng(kSeed);
    std::normal_distribution<double> inverse_depth_noise(0.0, 0.0045);
    const Eigen::Matrix3d rot = (Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ())).toRotationMatrix();
    std::vector<Eigen::Vector3f> pts;
    for (double u = -0.15; u <= 0.15; u += 0.006) {
      for (double v = -0.1; v <= 0.1; v += 0.006) {
        const Eigen::Vector3d q = c + rot * Eigen::Vector3d(u, v, 0);
        pts.push_back((q / (1.0 + q.z() * inverse_depth_noise(rng))).cast<float>());
      }
    }
    ShapeFitConfig config;
    config.plane_preference = 1.0;  // the hand-made rules: the better fit wins
    const auto fit = fitShape(pts, panelOutline(c, rot, 0.15, 0.1), {OutlineKind::kRectangle}, config);
    ASSERT_EQ(fit.shape, ShapeKind::kPlane) << "turn " << turn << ", seed " << kSeed;
    const Eigen::Vector3d normal = fit.orientation * Eigen::Vector3d::UnitZ();
    EXPECT_GT(std::abs(normal.dot(rot * Eigen::Vector3d::UnitZ())), 0.97) << "turn " << turn;  // within 14 degrees
    EXPECT_LT((fit.centre - c).norm(), 0.05) << "turn " << turn;
    EXPECT_NEAR(std::max(fit.size.x(), fit.size.y()), 0.3, 0.03) << "turn " << turn;
    EXPECT_NEAR(std::min(fit.size.x(), fit.size.y()), 0.2, 0.03) << "turn " << turn;
  }
}

/// What the cameras see of a closed tube `r` in radius and 2 `h` long centred at `c` along the unit `axis`: points
/// where rays from the camera first meet it (its near cap and the front of its side; `noise` m along the ray) and
/// the rays of its outline (the edge of what the rays meet, found by bisection in 720 image directions).
struct Tube {
  std::vector<Eigen::Vector3f> points;
  std::vector<Eigen::Vector3d> rays;
};

Tube tubeAt(const Eigen::Vector3d& c, const Eigen::Vector3d& axis, double r, double h, double noise,
            double border = std::numeric_limits<double>::infinity()) {
  auto hit = [&](const Eigen::Vector3d& ray) {  // distance along a unit ray to the tube; infinity when it misses
    double best = std::numeric_limits<double>::infinity();
    if (ray.x() / ray.z() > border) return best;  // beyond the image's right edge
    const double da = ray.dot(axis), ca = -c.dot(axis);
    const Eigen::Vector3d dp = ray - da * axis, cp = -c - ca * axis;  // across the axis, relative to the centre
    const double qa = dp.squaredNorm(), qb = 2 * dp.dot(cp), qc = cp.squaredNorm() - r * r;
    const double disc = qb * qb - 4 * qa * qc;
    if (disc >= 0 && qa > 1e-12) {
      const double t = (-qb - std::sqrt(disc)) / (2 * qa);
      if (std::abs(ca + t * da) <= h) best = t;
    }
    for (const double cap : {-h, h}) {
      if (std::abs(da) < 1e-12) continue;
      const double t = (cap - ca) / da;
      if ((cp + t * dp).norm() <= r) best = std::min(best, t);
    }
    return best;
  };
  std::mt19937 rng(kSeed);
  std::normal_distribution<double> n(0.0, noise);
  const Eigen::Vector3d u = c.normalized().unitOrthogonal(), v = c.normalized().cross(u);
  const double reach = std::hypot(r, h) * 1.5;
  std::uniform_real_distribution<double> square(-reach, reach);
  Tube tube;
  for (int i = 0; tube.points.size() < 1500 && i < 100000; ++i) {
    const Eigen::Vector3d ray = (c + square(rng) * u + square(rng) * v).normalized();
    const double t = hit(ray);
    if (std::isfinite(t)) tube.points.push_back((ray * (t + n(rng))).cast<float>());
  }
  for (int i = 0; i < 720; ++i) {
    const Eigen::Vector3d dir = std::cos(2 * M_PI * i / 720) * u + std::sin(2 * M_PI * i / 720) * v;
    double inside = 0, outside = reach;
    for (int k = 0; k < 30; ++k) {
      const double mid = (inside + outside) / 2;
      (std::isfinite(hit((c + mid * dir).normalized())) ? inside : outside) = mid;
    }
    tube.rays.push_back((c + inside * dir).normalized());
  }
  return tube;
}

TEST(ShapeFitter, TubeIsACylinderAlongItsAxis) {
  // 0.1 m across and 0.8 m long, across the line of sight 2 m away.
  const Eigen::Vector3d c(0.0, 0.2, 2.0);
  const Tube tube = tubeAt(c, Eigen::Vector3d::UnitX(), 0.05, 0.4, 0.003);
  const auto fit = fitShape(tube.points, tube.rays, {OutlineKind::kRectangle}, ShapeFitConfig{});
  ASSERT_EQ(fit.shape, ShapeKind::kCylinder) << "seed " << kSeed;
  EXPECT_NEAR(fit.size.z(), 0.8, 0.03);
  EXPECT_NEAR(fit.size.x(), 0.1, 0.01);
  EXPECT_LT((fit.centre - c).norm(), 0.02);
  const Eigen::Vector3d axis = fit.orientation * Eigen::Vector3d::UnitZ();
  EXPECT_GT(std::abs(axis.x()), 0.99);
}

TEST(ShapeFitter, AFarTubeLiesAlongItsAxisThoughItsDepthNoiseExceedsItsLength) {
  // 0.12 m across and 0.3 m long, 4.5 m away, across the line of sight and turned 30 degrees in the image; stereo's
  // ~9 cm of depth noise there spreads its points further along the line of sight than along the tube.
  const Eigen::Vector3d c(0.2, 0.1, 4.5);
  const Eigen::Vector3d axis = Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d::UnitX();
  const Tube tube = tubeAt(c, axis, 0.06, 0.15, 0.09);
  const ShapeFit fit = fitCylinder(tube.points, tube.rays);
  ASSERT_EQ(fit.shape, ShapeKind::kCylinder);
  EXPECT_GT(std::abs((fit.orientation * Eigen::Vector3d::UnitZ()).dot(axis)), 0.98);  // within 11 degrees
  EXPECT_NEAR(fit.size.z(), 0.3, 0.05);
  EXPECT_NEAR(fit.centre.norm(), c.norm(), 0.03 * c.norm());
}

TEST(ShapeFitter, ATubeCutByTheImageBorderIsCentredOnWhatIsSeenOfIt) {
  // 0.8 m long, 1.5 m away, turned 60 degrees into the scene, its far part beyond the image's right edge: the
  // outline runs along the border there. Its centre along the axis is the middle of the points seen (the outline's
  // span on the plane through the axis, border included, put it 7 % too far); whole, the middle of the tube.
  const Eigen::Vector3d c(0.0, 0.2, 1.5);
  const Eigen::Vector3d axis = Eigen::AngleAxisd(60 * M_PI / 180, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitX();
  const double border = 0.1;  // x / z of the image's right edge
  for (const bool cut : {false, true}) {
    const Tube tube = tubeAt(c, axis, 0.05, 0.4, 0.003, cut ? border : std::numeric_limits<double>::infinity());
    const ShapeFit fit = fitCylinder(tube.points, tube.rays);
    ASSERT_EQ(fit.shape, ShapeKind::kCylinder) << (cut ? "cut" : "whole");
    EXPECT_GT(std::abs((fit.orientation * Eigen::Vector3d::UnitZ()).dot(axis)), 0.99) << (cut ? "cut" : "whole");
    EXPECT_NEAR(fit.centre.norm(), c.norm(), 0.03 * c.norm()) << (cut ? "cut" : "whole");
    if (!cut) {
      EXPECT_LT((fit.centre - c).norm(), 0.03);
    }
  }
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
