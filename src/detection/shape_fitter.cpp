// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/shape_fitter.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>

#include <opencv2/imgproc.hpp>

namespace underwater_stereo {
namespace {

/// Box faces: RANSAC plane tolerance as a share of the object's range, iterations, seed.
constexpr double kBoxFaceTolerance = 0.005;
/// A box's extent along the line of sight under this share of its smaller visible side is a hidden depth.
constexpr double kHiddenDepthShare = 0.3;
constexpr int kRansacIterations = 100;
constexpr unsigned kRansacSeed = 1;
/// A plane is measured only where the line of sight meets it at more than ~14.5 degrees (|cos| of the angle
/// between ray and normal >= this): closer to edge-on, a pixel of outline moves its point on the plane by
/// metres (a near panel's outline reached 97 m), and a strip of points leaves the normal undetermined.
constexpr double kMinIncidence = 0.25;
/// A sphere's silhouette cone is fitted to the outline's own rays (off the image border) when there are this many,
/// and kept when its half angle is under kMaxConeHalfAngle (radians; a sphere filling a 60-degree view) and at most
/// kMaxConeGrowth times the outline's mean cone (a small cap of a sphere cut by the border says little of the rest).
constexpr std::size_t kMinConeRays = 20;
constexpr double kMaxConeHalfAngle = 0.5;
constexpr double kMaxConeGrowth = 2.0;

struct Pca {
  Eigen::Vector3d mean;
  Eigen::Matrix3d axes;      ///< columns: largest to smallest variance
  Eigen::Vector3d variance;  ///< largest first
};

Pca pca(const std::vector<Eigen::Vector3d>& pts) {
  Pca out;
  out.mean = Eigen::Vector3d::Zero();
  for (const auto& p : pts) out.mean += p;
  out.mean /= static_cast<double>(pts.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : pts) cov += (p - out.mean) * (p - out.mean).transpose();
  cov /= static_cast<double>(pts.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);  // ascending
  for (int i = 0; i < 3; ++i) {
    out.axes.col(i) = eig.eigenvectors().col(2 - i);
    out.variance[i] = std::max(0.0, eig.eigenvalues()[2 - i]);
  }
  return out;
}

/// Intersections of rays from the optical centre with the plane n.x = d (rays meeting it nearly edge-on,
/// under kMinIncidence, skipped).
std::vector<Eigen::Vector3d> onPlane(const std::vector<Eigen::Vector3d>& rays, const Eigen::Vector3d& n, double d) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& r : rays) {
    const double denom = n.dot(r);
    if (std::abs(denom) >= kMinIncidence * r.norm() && d / denom > 0) out.push_back(r * (d / denom));
  }
  return out;
}

/// Extent of points along a unit direction.
std::pair<double, double> span(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& dir) {
  double lo = std::numeric_limits<double>::max(), hi = -lo;
  for (const auto& p : pts) {
    lo = std::min(lo, p.dot(dir));
    hi = std::max(hi, p.dot(dir));
  }
  return {lo, hi};
}

/// Extent of points along a unit direction from their 2nd to their 98th percentile (robust to stray points).
std::pair<double, double> trimmedSpan(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& dir) {
  std::vector<double> along;
  along.reserve(pts.size());
  for (const auto& q : pts) along.push_back(q.dot(dir));
  std::sort(along.begin(), along.end());
  return {along[along.size() / 50], along[along.size() - 1 - along.size() / 50]};
}

/// RMS of the model's residuals after averaging them over a 6x6 grid of viewing directions: stereo noise
/// averages out, while a wrong model leaves a systematic pattern (a plane through a sphere's cap errs at
/// the centre and the rim in opposite directions).
double structuredRmse(const std::vector<Eigen::Vector3d>& pts, const std::vector<double>& residuals) {
  constexpr int kCells = 6;
  double x0 = 1e9, x1 = -1e9, y0 = 1e9, y1 = -1e9;
  for (const auto& p : pts) {
    x0 = std::min(x0, p.x() / p.z());
    x1 = std::max(x1, p.x() / p.z());
    y0 = std::min(y0, p.y() / p.z());
    y1 = std::max(y1, p.y() / p.z());
  }
  double sum[kCells][kCells] = {}, count[kCells][kCells] = {};
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const int cx = std::clamp(static_cast<int>((pts[i].x() / pts[i].z() - x0) / (x1 - x0 + 1e-12) * kCells), 0, kCells - 1);
    const int cy = std::clamp(static_cast<int>((pts[i].y() / pts[i].z() - y0) / (y1 - y0 + 1e-12) * kCells), 0, kCells - 1);
    sum[cy][cx] += residuals[i];
    count[cy][cx] += 1;
  }
  double total = 0, n = 0;
  for (int a = 0; a < kCells; ++a) {
    for (int b = 0; b < kCells; ++b) {
      if (count[a][b] < 3) continue;
      const double mean = sum[a][b] / count[a][b];
      total += mean * mean * count[a][b];
      n += count[a][b];
    }
  }
  return n > 0 ? std::sqrt(total / n) : 0.0;
}

double rms(const std::vector<double>& residuals) {
  double sum = 0;
  for (double r : residuals) sum += r * r;
  return residuals.empty() ? 0.0 : std::sqrt(sum / residuals.size());
}

Eigen::Quaterniond frameWithZ(const Eigen::Vector3d& z, const Eigen::Vector3d& x_hint) {
  const Eigen::Vector3d zn = z.normalized();
  Eigen::Vector3d x = (x_hint - x_hint.dot(zn) * zn);
  if (x.norm() < 1e-6) x = zn.unitOrthogonal();
  x.normalize();
  Eigen::Matrix3d r;
  r.col(0) = x;
  r.col(1) = zn.cross(x);
  r.col(2) = zn;
  return Eigen::Quaterniond(r);
}

/// A fitted model and how well it explains the points' shape (structuredRmse, lower is better).
struct Scored {
  ShapeFit fit;
  double structure_m = std::numeric_limits<double>::infinity();
};

/// The unit normal (towards the camera) of the plane through `pts` fitted where stereo measures: a plane's inverse
/// depth is linear in the normalised image coordinates, 1/z = a x/z + b y/z + c (disparity is linear across the
/// image), so (a, b, c) is the normal over the plane's distance. Fitted by least squares, then again without the
/// points off it by more than 3 robust deviations. Unlike the points' least-variance direction, it is not turned
/// by the depth noise, which grows with range and on a plain panel can exceed the panel's width (the panel then
/// looked edge-on). Zero when the points do not determine it.
Eigen::Vector3d disparityPlaneNormal(const std::vector<Eigen::Vector3d>& pts) {
  std::vector<Eigen::Vector3d> image;  // (x/z, y/z, 1) of each point in front of the camera
  std::vector<double> inverse_depth;
  for (const auto& q : pts) {
    if (!(q.z() > 0)) continue;
    image.push_back(q / q.z());
    inverse_depth.push_back(1.0 / q.z());
  }
  std::vector<char> use(image.size(), 1);
  Eigen::Vector3d abc = Eigen::Vector3d::Zero();
  for (int round = 0; round < 2; ++round) {
    Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
    Eigen::Vector3d atb = Eigen::Vector3d::Zero();
    int n = 0;
    for (std::size_t i = 0; i < image.size(); ++i) {
      if (!use[i]) continue;
      ata += image[i] * image[i].transpose();
      atb += image[i] * inverse_depth[i];
      ++n;
    }
    const Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
    if (n < 3 || ldlt.info() != Eigen::Success || ata.determinant() <= 1e-12 * std::pow(ata.trace(), 3)) {
      if (round == 0) return Eigen::Vector3d::Zero();
      break;  // too few points left on it: the first round's plane
    }
    abc = ldlt.solve(atb);
    std::vector<double> residuals(image.size());
    for (std::size_t i = 0; i < image.size(); ++i) residuals[i] = std::abs(abc.dot(image[i]) - inverse_depth[i]);
    std::vector<double> sorted = residuals;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double limit = 3 * 1.4826 * sorted[sorted.size() / 2];
    for (std::size_t i = 0; i < image.size(); ++i) use[i] = residuals[i] <= limit;
  }
  if (!abc.allFinite() || abc.norm() <= 0) return Eigen::Vector3d::Zero();
  return -abc.normalized();  // a x + b y + c z = 1 has its normal (a, b, c) away from the camera
}

/// The principal axes of `pts` with their depth noise taken out: each point moved along its ray onto the plane
/// through their mean with normal `surface` (disparityPlaneNormal). Stereo's depth noise, growing with range, can make the line of
/// sight the points' longest direction; the points' image positions are exact. A tube's visible half lies about the
/// plane through its axis, so its longest direction there is the axis. `p` when no plane is determined.
Pca alongSurface(const std::vector<Eigen::Vector3d>& pts, const Pca& p, const Eigen::Vector3d& n) {
  if (n.isZero()) return p;
  const double d = n.dot(p.mean);
  std::vector<Eigen::Vector3d> on_plane;
  for (const auto& q : pts) {
    const double denom = n.dot(q);
    if (std::abs(denom) >= kMinIncidence * q.norm() && d / denom > 0) on_plane.push_back(q * (d / denom));
  }
  return on_plane.size() >= 3 ? pca(on_plane) : p;
}

/// The points' plane's unit normal towards the camera: `surface` (disparityPlaneNormal), or their least-variance
/// direction when that is undetermined (zero).
Eigen::Vector3d facingNormal(const Pca& p, const Eigen::Vector3d& surface) {
  const Eigen::Vector3d n = surface.isZero() ? Eigen::Vector3d(p.axes.col(2)) : surface;
  return n.dot(p.mean) > 0 ? Eigen::Vector3d(-n) : n;
}

/// The plane of the points, its normal `surface` (disparityPlaneNormal; zero: their least-variance direction) and
/// its sides along the longest direction of `along` (alongSurface).
Scored fitPlane(const std::vector<Eigen::Vector3d>& pts, const Pca& p, const Eigen::Vector3d& surface, const Pca& along,
                const std::vector<Eigen::Vector3d>& rays) {
  Scored scored;
  ShapeFit& fit = scored.fit;
  const Eigen::Vector3d n = facingNormal(p, surface);
  if (-n.dot(p.mean.normalized()) < kMinIncidence) return scored;  // seen nearly edge-on
  fit.shape = ShapeKind::kPlane;
  std::vector<double> residuals;
  for (const auto& q : pts) residuals.push_back(n.dot(q - p.mean));
  fit.rmse_m = rms(residuals);
  scored.structure_m = structuredRmse(pts, residuals);
  const std::vector<Eigen::Vector3d> outline = onPlane(rays, n, n.dot(p.mean));
  const std::vector<Eigen::Vector3d>& extent_pts = outline.size() >= 3 ? outline : pts;
  // The points' longest direction within the plane, their depth noise taken out.
  Eigen::Vector3d u = along.axes.col(0);
  u = (u - u.dot(n) * n).normalized();
  const Eigen::Vector3d v = n.cross(u);
  const auto [u0, u1] = span(extent_pts, u);
  const auto [v0, v1] = span(extent_pts, v);
  const double depth = n.dot(p.mean);
  fit.centre = u * (u0 + u1) / 2 + v * (v0 + v1) / 2 + n * depth;
  fit.size = Eigen::Vector3d(u1 - u0, v1 - v0, 0.0);
  fit.orientation = frameWithZ(n, u);
  return scored;
}

/// Sphere whose silhouette is the cone of unit `axis` and `half_angle`: only its distance along the axis is fitted.
Scored fitSphereInCone(const std::vector<Eigen::Vector3d>& pts, const Eigen::Vector3d& axis, double half_angle) {
  Scored scored;
  ShapeFit& fit = scored.fit;
  fit.shape = ShapeKind::kSphere;
  const double s = std::sin(half_angle);
  auto cost = [&](double c) {
    double sum = 0.0;
    for (const auto& p : pts) {
      const double e = (p - c * axis).norm() - c * s;
      sum += e * e;
    }
    return sum;
  };
  // Golden-section search for the distance to the centre, bracketed around the points' depth.
  double median_range = 0.0;
  {
    std::vector<double> ranges;
    for (const auto& p : pts) ranges.push_back(p.norm());
    std::nth_element(ranges.begin(), ranges.begin() + ranges.size() / 2, ranges.end());
    median_range = ranges[ranges.size() / 2];
  }
  double a = median_range * 0.7, b = median_range / std::max(0.05, 1.0 - s) * 1.3;
  const double g = (std::sqrt(5.0) - 1) / 2;
  double c1 = b - g * (b - a), c2 = a + g * (b - a), f1 = cost(c1), f2 = cost(c2);
  for (int i = 0; i < 60; ++i) {
    if (f1 < f2) {
      b = c2;
      c2 = c1;
      f2 = f1;
      c1 = b - g * (b - a);
      f1 = cost(c1);
    } else {
      a = c1;
      c1 = c2;
      f1 = f2;
      c2 = a + g * (b - a);
      f2 = cost(c2);
    }
  }
  const double c = (a + b) / 2;
  fit.centre = c * axis;
  fit.size = Eigen::Vector3d::Constant(2 * c * s);
  std::vector<double> residuals;
  for (const auto& p : pts) residuals.push_back((p - fit.centre).norm() - c * s);
  fit.rmse_m = rms(residuals);
  scored.structure_m = structuredRmse(pts, residuals);
  return scored;
}

/// The outline's cone taken as its rays' mean direction and their mean angle from it.
std::pair<Eigen::Vector3d, double> meanCone(const std::vector<Eigen::Vector3d>& rays) {
  Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  for (const auto& r : rays) axis += r;
  axis.normalize();
  double half_angle = 0.0;
  for (const auto& r : rays) half_angle += std::acos(std::clamp(r.dot(axis), -1.0, 1.0));
  return {axis, half_angle / static_cast<double>(rays.size())};
}

/// The circular cone through the rays (least squares: r . w = 1 with w = axis / cos(half angle)), which a part of
/// the outline determines as well as all of it: the silhouette of a sphere cut by the image border. Nothing when
/// fewer than kMinConeRays rays, or when they do not pin down a cone narrower than kMaxConeHalfAngle.
std::optional<std::pair<Eigen::Vector3d, double>> coneThrough(const std::vector<Eigen::Vector3d>& rays) {
  if (rays.size() < kMinConeRays) return std::nullopt;
  Eigen::Matrix3d rtr = Eigen::Matrix3d::Zero();
  Eigen::Vector3d rt1 = Eigen::Vector3d::Zero();
  for (const auto& r : rays) {
    rtr += r * r.transpose();
    rt1 += r;
  }
  const Eigen::Vector3d w = rtr.ldlt().solve(rt1);
  if (!w.allFinite() || w.norm() <= 1.0) return std::nullopt;
  const double half_angle = std::acos(1.0 / w.norm());
  if (!(half_angle < kMaxConeHalfAngle)) return std::nullopt;
  return std::make_pair(Eigen::Vector3d(w.normalized()), half_angle);
}

/// Cylinder lying along the longest direction of `along` (alongSurface); diameter and length from the outline on the plane through
/// the axis that faces the camera; the axis sits a radius behind the visible surface, its centre midway along
/// the points.
Scored fitCylinder(const std::vector<Eigen::Vector3d>& pts, const Pca& p, const Pca& along,
                   const std::vector<Eigen::Vector3d>& rays) {
  Scored scored;
  ShapeFit& fit = scored.fit;
  const Eigen::Vector3d axis = along.axes.col(0);
  Eigen::Vector3d view = p.mean - p.mean.dot(axis) * axis;  // towards the object, across the axis
  view.normalize();
  const Eigen::Vector3d across = axis.cross(view).normalized();
  // First pass: radius from the outline on the plane through the visible surface.
  std::vector<Eigen::Vector3d> outline = onPlane(rays, view, view.dot(p.mean));
  if (outline.size() < 3) return scored;
  fit.shape = ShapeKind::kCylinder;
  auto [w0, w1] = span(outline, across);
  double radius = (w1 - w0) / 2;
  // Second pass: the axis plane lies ~ radius * pi/4 behind the mean of the visible half-surface.
  const Eigen::Vector3d on_axis = p.mean + view * radius * M_PI / 4;
  outline = onPlane(rays, view, view.dot(on_axis));
  std::tie(w0, w1) = span(outline, across);
  radius = (w1 - w0) / 2;
  const auto [l0, l1] = span(outline, axis);
  // Along the axis the centre is the middle of the points (2nd to 98th percentile): the outline's span on this
  // plane runs along the image border where the tube is cut by it, and is met at a grazing angle by the rays
  // of a tube turned into the scene; both put the centre too far.
  const auto [a0, a1] = trimmedSpan(pts, axis);
  const Eigen::Vector3d base = on_axis - axis * on_axis.dot(axis) - across * on_axis.dot(across);
  fit.centre = base + axis * (a0 + a1) / 2 + across * (w0 + w1) / 2;
  fit.size = Eigen::Vector3d(2 * radius, 2 * radius, l1 - l0);
  fit.orientation = frameWithZ(axis, across);
  std::vector<double> residuals;
  for (const auto& q : pts) {
    const Eigen::Vector3d rel = q - fit.centre;
    residuals.push_back((rel - rel.dot(axis) * axis).norm() - radius);
  }
  fit.rmse_m = rms(residuals);
  scored.structure_m = structuredRmse(pts, residuals);
  return scored;
}

/// The plane holding most points within `tolerance` (RANSAC, fixed seed: repeatable).
struct DominantPlane {
  Eigen::Vector3d normal;
  std::vector<bool> inlier;  ///< per point
  std::size_t inliers = 0;
};

DominantPlane dominantPlane(const std::vector<Eigen::Vector3d>& pts, double tolerance, const Eigen::Vector3d& fallback) {
  std::mt19937 rng(kRansacSeed);
  std::uniform_int_distribution<std::size_t> pick(0, pts.size() - 1);
  DominantPlane best{fallback, std::vector<bool>(pts.size(), false), 0};
  Eigen::Vector3d best_point = Eigen::Vector3d::Zero();
  for (int it = 0; it < kRansacIterations; ++it) {
    const Eigen::Vector3d a = pts[pick(rng)], b = pts[pick(rng)], c = pts[pick(rng)];
    Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-12) continue;
    n.normalize();
    std::size_t count = 0;
    for (const auto& q : pts) count += std::abs(n.dot(q - a)) < tolerance;
    if (count > best.inliers) {
      best.inliers = count;
      best.normal = n;
      best_point = a;
    }
  }
  for (std::size_t i = 0; i < pts.size() && best.inliers > 0; ++i) {
    best.inlier[i] = std::abs(best.normal.dot(pts[i] - best_point)) < tolerance;
  }
  return best;
}

/// Box aligned with its largest visible face (RANSAC) and, within that face's plane, with the tightest
/// rectangle around all points; spanning the points' 2nd to 98th percentiles (robust to stray points).
Scored fitBox(const std::vector<Eigen::Vector3d>& pts, const Pca& p) {
  Scored scored;
  std::vector<double> ranges;
  for (const auto& q : pts) ranges.push_back(q.norm());
  std::nth_element(ranges.begin(), ranges.begin() + ranges.size() / 2, ranges.end());
  Eigen::Matrix3d axes;
  axes.col(2) = dominantPlane(pts, kBoxFaceTolerance * ranges[ranges.size() / 2], p.axes.col(2)).normal;
  const Eigen::Vector3d e1 = axes.col(2).unitOrthogonal(), e2 = axes.col(2).cross(e1);
  std::vector<cv::Point2f> flat;
  for (const auto& q : pts) flat.emplace_back(static_cast<float>(q.dot(e1)), static_cast<float>(q.dot(e2)));
  const float angle = cv::minAreaRect(flat).angle * static_cast<float>(M_PI / 180);
  axes.col(0) = std::cos(angle) * e1 + std::sin(angle) * e2;
  axes.col(1) = axes.col(2).cross(axes.col(0));
  ShapeFit& fit = scored.fit;
  fit.shape = ShapeKind::kBox;
  fit.centre = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) {
    const auto [lo, hi] = trimmedSpan(pts, axes.col(a));
    fit.centre += axes.col(a) * (lo + hi) / 2;
    fit.size[a] = hi - lo;
  }
  // Seen face-on, a box shows no side along its axis nearest the line of sight: its depth there is hidden. It
  // is taken as the mean of the two visible sides (the centre goes half of it behind the face), not zero.
  const Eigen::Vector3d view = p.mean.normalized();
  int deep = 0;
  for (int a = 1; a < 3; ++a) deep = std::abs(axes.col(a).dot(view)) > std::abs(axes.col(deep).dot(view)) ? a : deep;
  const double side_a = fit.size[(deep + 1) % 3], side_b = fit.size[(deep + 2) % 3];
  if (fit.size[deep] < kHiddenDepthShare * std::min(side_a, side_b)) {
    const double hidden = (side_a + side_b) / 2;
    const Eigen::Vector3d away = axes.col(deep) * (axes.col(deep).dot(view) >= 0 ? 1.0 : -1.0);
    fit.centre += away * (hidden - fit.size[deep]) / 2;
    fit.hidden_depth_m = std::abs(away.dot(view)) * (hidden - fit.size[deep]) / 2;
    fit.size[deep] = hidden;
  }
  fit.orientation = Eigen::Quaterniond(axes);
  std::vector<double> residuals;  // distance to the nearest face
  for (const auto& q : pts) {
    const Eigen::Vector3d local = axes.transpose() * (q - fit.centre);
    double nearest = std::numeric_limits<double>::max();
    for (int a = 0; a < 3; ++a) nearest = std::min(nearest, std::abs(std::abs(local[a]) - fit.size[a] / 2));
    residuals.push_back(nearest);
  }
  fit.rmse_m = rms(residuals);
  return scored;
}

/// Elongation of the outline (as seen): ratio of its principal extents in the image plane.
double outlineElongation(const std::vector<Eigen::Vector3d>& rays) {
  std::vector<Eigen::Vector3d> flat;
  for (const auto& r : rays) flat.push_back(r / r.z());
  const Pca p = pca(flat);
  const auto [a0, a1] = span(flat, p.axes.col(0));
  const auto [b0, b1] = span(flat, p.axes.col(1));
  return (a1 - a0) / std::max(1e-9, b1 - b0);
}

/// The hand-made decision (no shape model): stereo smoothing flattens smooth curved surfaces, so the 2D outline
/// decides close calls: a round outline is a sphere unless the plane is clearly better, anything else a plane
/// unless the curve is. Flat faces of clearly different shading: a box, whatever its outline (a box seen
/// corner-on is a hexagon, close to an ellipse). `curved`: the cylinder for an elongated outline, else the sphere;
/// `unknown`: what is reported when neither fits.
ShapeFit handMadeDecision(const std::vector<Eigen::Vector3d>& pts, const Pca& p, const OutlineCues& cues,
                          const ShapeFitConfig& config, const Scored& plane, const Scored& curved,
                          const ShapeFit& unknown) {
  const bool curved_ok = curved.fit.shape != ShapeKind::kUnknown && curved.fit.centre.allFinite();
  if (cues.face_contrast >= config.box_face_contrast) return fitBox(pts, p).fit;
  const bool round = cues.outline == OutlineKind::kCircle || cues.outline == OutlineKind::kEllipse;
  const bool curved_wins = round ? curved.structure_m < plane.structure_m * config.plane_preference
                                 : curved.structure_m * config.plane_preference < plane.structure_m;
  if (curved_ok && curved_wins) return curved.fit;
  if (plane.fit.shape != ShapeKind::kUnknown) return plane.fit;
  if (curved_ok) return curved.fit;
  return unknown;
}

/// A fit's residual relative to `range`, 1 when the model could not be fitted.
double relative(double value_m, double range) {
  return std::isfinite(value_m) ? std::min(1.0, value_m / range) : 1.0;
}

/// The features of shapeFeatureNames(): the outline and shading cues, then the fits' evidence.
std::vector<float> shapeFeatures(const std::vector<Eigen::Vector3d>& pts, const Pca& p, const Eigen::Vector3d& surface,
                                 const OutlineCues& cues,
                                 const Scored& plane, const Scored& sphere, const Scored& cylinder, double elongation) {
  std::vector<double> ranges;
  for (const auto& q : pts) ranges.push_back(q.norm());
  std::nth_element(ranges.begin(), ranges.begin() + ranges.size() / 2, ranges.end());
  const double range = std::max(1e-3, ranges[ranges.size() / 2]);
  const Eigen::Vector3d view = p.mean.normalized();
  // Depth spread (10th to 90th percentile along the line of sight) against the outline's width at that range.
  std::vector<double> depth;
  for (const auto& q : pts) depth.push_back(q.dot(view));
  std::sort(depth.begin(), depth.end());
  const double spread = depth[depth.size() * 9 / 10] - depth[depth.size() / 10];
  const double sphere_distance = sphere.fit.centre.norm(), radius = sphere.fit.size.x() / 2;
  const double width = sphere_distance > 0 ? 2 * radius * range / sphere_distance : 0.0;
  // The points' bulge towards the camera: residuals from their plane in disparity (surface) of the inner half (by
  // distance from the centroid within the plane) minus the outer half's.
  const Eigen::Vector3d n = facingNormal(p, surface);
  std::vector<std::pair<double, double>> radial;  // (distance in the plane, residual towards the camera)
  for (const auto& q : pts) {
    const Eigen::Vector3d d = q - p.mean;
    radial.emplace_back((d - n.dot(d) * n).norm(), n.dot(d));
  }
  std::sort(radial.begin(), radial.end());
  double inner = 0, outer = 0;
  const std::size_t half = radial.size() / 2;
  for (std::size_t i = 0; i < radial.size(); ++i) (i < half ? inner : outer) += radial[i].second;
  const double bulge = (inner / std::max<std::size_t>(1, half) - outer / std::max<std::size_t>(1, radial.size() - half)) / range;
  // Shares of the points on the dominant plane and on it and the next one (a box's faces).
  const double tolerance = kBoxFaceTolerance * range;
  const DominantPlane first = dominantPlane(pts, tolerance, p.axes.col(2));
  std::vector<Eigen::Vector3d> rest;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!first.inlier[i]) rest.push_back(pts[i]);
  }
  const std::size_t second = rest.size() >= 3 ? dominantPlane(rest, tolerance, p.axes.col(2)).inliers : 0;
  const double total = static_cast<double>(pts.size());
  ShapeFeatureRow row;
  row.set("outline_kind", static_cast<double>(cues.outline));
  row.set("solidity", cues.solidity);
  row.set("circularity", cues.circularity);
  row.set("aspect", std::min(cues.aspect, 50.0));
  row.set("rect_fill", cues.rect_fill);
  row.set("corners", std::min(cues.corners, 50.0));
  row.set("border_share", cues.border_share);
  row.set("ellipse_residual", cues.ellipse_residual);
  row.set("quad_tolerance", cues.quad_tolerance);
  row.set("hexagon_tolerance", cues.hexagon_tolerance);
  row.set("octagon_tolerance", cues.octagon_tolerance);
  row.set("decagon_tolerance", cues.decagon_tolerance);
  row.set("log_face_contrast", std::log1p(std::max(0.0, cues.face_contrast)));
  row.set("shading_spread", cues.shading_spread);
  row.set("shading_linear", cues.shading_linear);
  row.set("shading_quadratic", cues.shading_quadratic);
  row.set("shading_across", cues.shading_across);
  row.set("plane_structure", relative(plane.structure_m, range));
  row.set("sphere_structure", relative(sphere.structure_m, range));
  row.set("cylinder_structure", relative(cylinder.structure_m, range));
  row.set("plane_rmse", relative(plane.fit.shape == ShapeKind::kUnknown ? NAN : plane.fit.rmse_m, range));
  row.set("sphere_rmse", relative(sphere.fit.rmse_m, range));
  row.set("cylinder_rmse", relative(cylinder.fit.shape == ShapeKind::kUnknown ? NAN : cylinder.fit.rmse_m, range));
  row.set("pca_middle", std::sqrt(p.variance[1] / std::max(1e-12, p.variance[0])));
  row.set("pca_smallest", std::sqrt(p.variance[2] / std::max(1e-12, p.variance[0])));
  row.set("depth_spread", width > 0 ? std::min(5.0, spread / width) : 5.0);
  row.set("sphere_depth", radius > 0 ? std::clamp((sphere_distance - range) / radius, -5.0, 5.0) : 0.0);
  row.set("elongation", std::min(elongation, 50.0));
  row.set("surface_incidence", std::abs(n.dot(view)));
  row.set("face_share", first.inliers / total);
  row.set("two_face_share", (first.inliers + second) / total);
  row.set("bulge", std::clamp(bulge, -1.0, 1.0));
  row.set("log_points", std::log(total));
  row.set("range_m", range);
  return row.values();
}

}  // namespace

std::vector<std::string> ShapeFitConfig::validate() const {
  std::vector<std::string> p;
  if (!(min_points >= 3 && min_points <= 1e6)) p.push_back("shape.min_points must be in [3, 1000000]");
  if (!(plane_preference >= 1.0 && plane_preference <= 10.0)) p.push_back("shape.plane_preference must be in [1, 10]");
  if (!(min_elongation >= 1.0 && min_elongation <= 20.0)) p.push_back("shape.min_elongation must be in [1, 20]");
  if (!(box_face_contrast >= 0.01 && box_face_contrast <= 1000)) {
    p.push_back("shape.box_face_contrast must be in [0.01, 1000]");
  }
  return p;
}

ShapeFit fitShape(const std::vector<Eigen::Vector3f>& points_f, const std::vector<Eigen::Vector3d>& outline_rays,
                  const OutlineCues& cues, const ShapeFitConfig& config) {
  std::vector<Eigen::Vector3d> pts;
  pts.reserve(points_f.size());
  for (const auto& p : points_f) pts.push_back(p.cast<double>());
  ShapeFit unknown;
  if (pts.empty()) return unknown;
  const Pca p = pca(pts);
  unknown.centre = p.mean;
  for (int i = 0; i < 3; ++i) {
    const auto [lo, hi] = span(pts, Eigen::Vector3d::Unit(i));
    unknown.size[i] = hi - lo;
  }
  if (pts.size() < config.min_points || outline_rays.size() < 5) return unknown;

  const Eigen::Vector3d surface = disparityPlaneNormal(pts);
  const Pca along = alongSurface(pts, p, surface);
  const Scored plane = fitPlane(pts, p, surface, along, outline_rays);
  const auto [mean_axis, mean_half_angle] = meanCone(outline_rays);
  const Scored sphere = fitSphereInCone(pts, mean_axis, mean_half_angle);  // what the shape is decided on
  const Scored cylinder = fitCylinder(pts, p, along, outline_rays);
  const double elongation = outlineElongation(outline_rays);
  std::vector<float> features = shapeFeatures(pts, p, surface, cues, plane, sphere, cylinder, elongation);
  for (float& f : features) f = std::isfinite(f) ? f : 0.0f;  // a degenerate fit says nothing; never NaN to the model
  auto usable = [](const Scored& s) { return s.fit.shape != ShapeKind::kUnknown && s.fit.centre.allFinite(); };
  ShapeFit chosen = unknown;
  const ShapeKind learnt = config.model ? config.model->classify(features).shape : ShapeKind::kUnknown;
  if (learnt == ShapeKind::kBox) chosen = fitBox(pts, p).fit;
  else if (learnt == ShapeKind::kPlane && usable(plane)) chosen = plane.fit;
  else if (learnt == ShapeKind::kSphere && usable(sphere)) chosen = sphere.fit;
  else if (learnt == ShapeKind::kCylinder && usable(cylinder)) chosen = cylinder.fit;
  else chosen = handMadeDecision(pts, p, cues, config, plane, elongation >= config.min_elongation ? cylinder : sphere, unknown);
  if (chosen.shape == ShapeKind::kSphere) {
    // Its pose from the cone through the outline's own rays (off the image border), a sphere's exact silhouette:
    // the mean cone (what the shape was decided on) is only near it, and where the border cuts the sphere it is
    // the visible part's, too narrow and turned towards the image.
    std::vector<Eigen::Vector3d> silhouette;
    for (std::size_t i = 0; i < outline_rays.size(); ++i) {
      if (cues.on_border.size() != outline_rays.size() || !cues.on_border[i]) silhouette.push_back(outline_rays[i]);
    }
    // Taken when it is at most kMaxConeGrowth times as wide as the mean cone (a small cap of a sphere says little
    // about the rest) and the points lie on the sphere at least as well.
    const auto cone = coneThrough(silhouette);
    if (cone && cone->second <= kMaxConeGrowth * mean_half_angle) {
      const ShapeFit whole = fitSphereInCone(pts, cone->first, cone->second).fit;
      if (whole.rmse_m <= chosen.rmse_m) chosen = whole;
    }
  }
  chosen.features = std::move(features);
  return chosen;
}

ShapeFit fitCylinder(const std::vector<Eigen::Vector3f>& points, const std::vector<Eigen::Vector3d>& outline_rays) {
  std::vector<Eigen::Vector3d> pts;
  for (const auto& q : points) pts.push_back(q.cast<double>());
  if (pts.size() < 3) return ShapeFit{};
  const Pca p = pca(pts);
  return fitCylinder(pts, p, alongSurface(pts, p, disparityPlaneNormal(pts)), outline_rays).fit;
}

}  // namespace underwater_stereo
