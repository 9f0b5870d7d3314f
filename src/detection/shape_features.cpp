// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/shape_features.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/candidate_finder.h"

namespace underwater_stereo {
namespace {

/// Object pixels sampled on a grid to about this many for the shading fits.
constexpr int kShadingSamples = 2000;

/// Shares of the grey-level variance explained by a linear ramp, beyond it by a quadratic surface, and by a parabola
/// across `long_axis` (a unit image direction, the outline's longest) alone.
void shadingFits(const cv::Mat& grey, const cv::Mat& mask, const cv::Point2d& long_axis, OutlineCues& cues) {
  constexpr int kTerms = 8;  // 1, x, y, x^2, y^2, xy, t, t^2 with t across long_axis
  const int step = std::max(1, static_cast<int>(std::sqrt(double(cv::countNonZero(mask > 127)) / kShadingSamples)));
  const double scale = std::max(1.0, 0.5 * std::max(grey.cols, grey.rows));
  std::vector<cv::Vec<double, kTerms>> rows;
  std::vector<double> values;
  double sum = 0, sum2 = 0;
  for (int v = 0; v < grey.rows; v += step) {
    for (int u = 0; u < grey.cols; u += step) {
      if (mask.at<std::uint8_t>(v, u) <= 127) continue;
      const double x = (u - grey.cols / 2.0) / scale, y = (v - grey.rows / 2.0) / scale, g = grey.at<std::uint8_t>(v, u);
      const double t = x * long_axis.y - y * long_axis.x;
      rows.emplace_back(1, x, y, x * x, y * y, x * y, t, t * t);
      values.push_back(g);
      sum += g;
      sum2 += g * g;
    }
  }
  const double n = static_cast<double>(values.size());
  if (n < 12 || sum <= 0) return;
  const double mean = sum / n, variance = std::max(0.0, sum2 / n - mean * mean);
  cues.shading_spread = std::sqrt(variance) / mean;
  if (variance < 1e-6) return;
  // Share of the variance explained by the terms in `use` (least squares).
  auto explained = [&](std::initializer_list<int> use) {
    const int k = static_cast<int>(use.size());
    cv::Mat ata = cv::Mat::zeros(k, k, CV_64F), atb = cv::Mat::zeros(k, 1, CV_64F), x;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      int a = 0;
      for (int p : use) {
        int b = 0;
        for (int q : use) ata.at<double>(a, b++) += rows[i][p] * rows[i][q];
        atb.at<double>(a++) += rows[i][p] * values[i];
      }
    }
    if (!cv::solve(ata, atb, x, cv::DECOMP_SVD)) return 0.0;
    double residual = 0;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      double model = 0;
      int a = 0;
      for (int p : use) model += rows[i][p] * x.at<double>(a++);
      residual += (values[i] - model) * (values[i] - model);
    }
    return std::clamp(1.0 - residual / n / variance, 0.0, 1.0);
  };
  cues.shading_linear = explained({0, 1, 2});
  cues.shading_quadratic = std::max(0.0, explained({0, 1, 2, 3, 4, 5}) - cues.shading_linear);
  cues.shading_across = explained({0, 6, 7});
}

/// An outline is thinned to about this many points for its ellipse (a full-resolution contour has thousands; the
/// fit took 0.27 ms for 1600).
constexpr std::size_t kEllipsePoints = 400;

/// Mean |r - 1| of `outline` (every k-th point, to kEllipsePoints) in the frame of the ellipse fitted to them
/// (r = 1 on it); 1 when none fits.
double ellipseResidual(const std::vector<cv::Point>& outline) {
  const std::size_t step = (outline.size() + kEllipsePoints - 1) / kEllipsePoints;
  std::vector<cv::Point> points;
  for (std::size_t i = 0; i < outline.size(); i += std::max<std::size_t>(1, step)) points.push_back(outline[i]);
  if (points.size() < 6) return 1.0;
  const cv::RotatedRect e = cv::fitEllipse(points);
  const double a = e.size.width / 2, b = e.size.height / 2;
  if (!(a > 0.5 && b > 0.5)) return 1.0;
  const double c = std::cos(e.angle * M_PI / 180), s = std::sin(e.angle * M_PI / 180);
  double sum = 0;
  for (const cv::Point& p : points) {
    const double dx = p.x - e.center.x, dy = p.y - e.center.y;
    const double x = (c * dx + s * dy) / a, y = (-s * dx + c * dy) / b;
    sum += std::abs(std::hypot(x, y) - 1);
  }
  return std::min(1.0, sum / points.size());
}

/// The smallest approxPolyDP tolerance at which the convex polygon `hull` keeps at most `vertices` vertices, over
/// `scale` (bisection to 1/1024 of the largest tolerance tried, scale itself).
double polygonTolerance(const std::vector<cv::Point>& hull, std::size_t vertices, double scale) {
  if (hull.size() <= vertices || scale <= 0) return 0.0;
  double lo = 0, hi = scale;
  std::vector<cv::Point> simplified;
  for (int i = 0; i < 10; ++i) {
    const double mid = (lo + hi) / 2;
    cv::approxPolyDP(hull, simplified, mid, true);
    (simplified.size() <= vertices ? hi : lo) = mid;
  }
  return hi / scale;
}

}  // namespace

bool onImageBorder(const cv::Point& p, const cv::Size& frame) {
  return p.x <= 1 || p.y <= 1 || p.x >= frame.width - 2 || p.y >= frame.height - 2;
}

OutlineCues outlineCues(const Candidate& c, const cv::Mat& bgr_roi, const cv::Size& frame) {
  if (c.contour.size() < 3) throw std::invalid_argument("outlineCues: contour of fewer than 3 points");
  if (bgr_roi.type() != CV_8UC3 || bgr_roi.size() != c.roi.size() || c.mask.size() != c.roi.size() ||
      c.mask.type() != CV_8UC1) {
    throw std::invalid_argument("outlineCues: image and mask must be BGR8 and CV_8U of the candidate's roi size");
  }
  OutlineCues cues;
  cues.outline = c.outline;
  cues.face_contrast = c.face_contrast;
  const double area = cv::contourArea(c.contour), perimeter = cv::arcLength(c.contour, true);
  std::vector<cv::Point> hull, corners;
  cv::convexHull(c.contour, hull);
  const double hull_area = cv::contourArea(hull);
  cues.solidity = hull_area > 0 ? area / hull_area : 1.0;
  cues.circularity = perimeter > 0 ? 4 * M_PI * area / (perimeter * perimeter) : 0.0;
  const cv::RotatedRect box = cv::minAreaRect(c.contour);
  const double long_side = std::max(box.size.width, box.size.height), short_side = std::min(box.size.width, box.size.height);
  cues.aspect = long_side / std::max(1.0, short_side);
  cues.rect_fill = box.size.area() > 0 ? area / box.size.area() : 1.0;
  cv::approxPolyDP(c.contour, corners, 0.02 * perimeter, true);
  cues.corners = static_cast<double>(corners.size());
  std::vector<cv::Point> off_border;
  for (const cv::Point& p : c.contour) {
    cues.on_border.push_back(onImageBorder(p, frame));
    if (!cues.on_border.back()) off_border.push_back(p);
  }
  cues.border_share = double(c.contour.size() - off_border.size()) / c.contour.size();
  cues.ellipse_residual = ellipseResidual(off_border.size() >= 6 ? off_border : c.contour);
  // approxPolyDP keeps the first point as a vertex: start the hull at its point farthest from the centre (a corner).
  const cv::Point2f centre = box.center;
  const auto far = std::max_element(hull.begin(), hull.end(), [&](const cv::Point& a, const cv::Point& b) {
    return cv::norm(cv::Point2f(a) - centre) < cv::norm(cv::Point2f(b) - centre);
  });
  std::rotate(hull.begin(), far, hull.end());
  const double size = std::sqrt(std::max(1.0, area));  // tolerances relative to the outline's size
  cues.quad_tolerance = polygonTolerance(hull, 4, size);
  cues.hexagon_tolerance = polygonTolerance(hull, 6, size);
  cues.octagon_tolerance = polygonTolerance(hull, 8, size);
  cues.decagon_tolerance = polygonTolerance(hull, 10, size);
  cv::Mat grey;
  cv::cvtColor(bgr_roi, grey, cv::COLOR_BGR2GRAY);
  const double angle = box.angle * M_PI / 180;  // the direction of box.size.width
  const cv::Point2d width_axis(std::cos(angle), std::sin(angle));
  shadingFits(grey, c.mask, box.size.width >= box.size.height ? width_axis : cv::Point2d(-width_axis.y, width_axis.x),
              cues);
  return cues;
}

const std::vector<std::string>& shapeFeatureNames() {
  static const std::vector<std::string> names{
      "outline_kind", "solidity", "circularity", "aspect", "rect_fill", "corners", "border_share", "ellipse_residual",
      "quad_tolerance", "hexagon_tolerance", "octagon_tolerance", "decagon_tolerance",
      "log_face_contrast",
      "shading_spread", "shading_linear", "shading_quadratic", "shading_across", "plane_structure", "sphere_structure",
      "cylinder_structure", "plane_rmse", "sphere_rmse", "cylinder_rmse", "pca_middle", "pca_smallest", "depth_spread",
      "sphere_depth", "elongation", "surface_incidence", "face_share", "two_face_share", "bulge", "log_points", "range_m"};
  return names;
}

void ShapeFeatureRow::set(const std::string& name, double value) {
  const std::vector<std::string>& names = shapeFeatureNames();
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) throw std::logic_error("ShapeFeatureRow::set: no shape feature named " + name);
  const auto i = static_cast<std::size_t>(it - names.begin());
  if (set_[i]) throw std::logic_error("ShapeFeatureRow::set: " + name + " set twice");
  values_[i] = static_cast<float>(value);
  set_[i] = true;
}

std::vector<float> ShapeFeatureRow::values() const {
  for (std::size_t i = 0; i < set_.size(); ++i) {
    if (!set_[i]) throw std::logic_error("ShapeFeatureRow::values: " + shapeFeatureNames()[i] + " not set");
  }
  return values_;
}

}  // namespace underwater_stereo
