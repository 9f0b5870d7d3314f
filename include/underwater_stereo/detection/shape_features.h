// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file What an object's outline and shading say about its shape (OutlineCues), and the names of the features a
/// shape model (shape_model.h) decides from: these 2D cues and the 3D fits' evidence (shape_fitter.h).

#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "underwater_stereo/detection/outline_kind.h"

namespace underwater_stereo {

struct Candidate;

/// What the 2D image says about the shape. Defaults: a clean, unshaded, uncut outline.
struct OutlineCues {
  OutlineKind outline = OutlineKind::kPolygon;  ///< the contour's class (classifyOutline)
  double face_contrast = 0.0;                   ///< Candidate::face_contrast: flat faces of different shading
  double solidity = 1.0;      ///< contour area / its convex hull's
  double circularity = 1.0;   ///< 4 pi area / perimeter^2 (1: a circle)
  double aspect = 1.0;        ///< long / short side of the tightest rotated rectangle
  double rect_fill = 1.0;     ///< contour area / that rectangle's area (1: a rectangle, pi/4: an ellipse)
  double corners = 0.0;       ///< vertices of the contour simplified to 2 % of its perimeter
  double border_share = 0.0;  ///< share of the contour's points on the image border (a cut outline)
  /// Mean |r - 1| of the outline's points off the border in the frame of the ellipse fitted to them (r = 1 on
  /// it): 0 for an ellipse (a sphere's outline), 0.04 for a regular hexagon, 0.10 for a square or a rectangle.
  double ellipse_residual = 0.0;
  /// The smallest tolerance, over the square root of the area, at which the outline's hull simplifies to at most
  /// 4 vertices (~0 for a panel or a box seen face-on, 0.16 for a circle) and to at most 6 (a box's hexagon).
  double quad_tolerance = 0.0;
  double hexagon_tolerance = 0.0;
  /// The same at most 8 vertices: ~0 for a box's hexagon, larger for a rounded outline (a tube's ends: 0.07 for a
  /// 3:1 stadium; a circle: 0.045).
  double octagon_tolerance = 0.0;
  double decagon_tolerance = 0.0;  ///< the same at most 10 vertices
  std::vector<bool> on_border = {};  ///< per contour point: on the image border, not the object's edge (empty: none)
  double shading_spread = 0.0;     ///< grey-level standard deviation / mean over the object's pixels
  double shading_linear = 0.0;     ///< share of the grey-level variance a linear ramp across the region explains
  double shading_quadratic = 0.0;  ///< share a quadratic surface explains beyond the ramp (a lit ball's highlight)
  /// Share a parabola across the outline's longest direction alone explains (a lit tube: shading that changes
  /// across its axis, not along it).
  double shading_across = 0.0;
};

/// The cues of candidate `c` (full-resolution contour and roi-sized mask) in the left image's `bgr_roi`
/// (BGR8 of c.roi) of a frame of `frame` size. @throw std::invalid_argument when bgr_roi is not c.roi's size
/// and BGR8, or the contour has fewer than 3 points.
OutlineCues outlineCues(const Candidate& c, const cv::Mat& bgr_roi, const cv::Size& frame);

/// Whether an outline's point lies on the border of a `frame`-sized image (within a pixel of it): there the
/// outline is the image's edge, not the object's.
bool onImageBorder(const cv::Point& p, const cv::Size& frame);

/// Number of features per object, and their names in order: the outline and shading cues, then the 3D
/// fits' evidence (residuals of the plane, sphere and cylinder fits relative to range, principal extents,
/// depth spread against the outline's width, dominant planes' shares, the bulge of the points towards the
/// camera, point count, range).
constexpr int kShapeFeatureCount = 34;
const std::vector<std::string>& shapeFeatureNames();

/// One object's shape features, set by name and handed out in shapeFeatureNames()' order, so that the order a
/// model reads is kept in that one list. @throw std::logic_error (a build's own mistake, not bad input) from set() for
/// a name not in the list or set twice, and from values() while any is unset.
class ShapeFeatureRow {
 public:
  void set(const std::string& name, double value);
  std::vector<float> values() const;

 private:
  std::vector<float> values_ = std::vector<float>(kShapeFeatureCount);
  std::vector<bool> set_ = std::vector<bool>(kShapeFeatureCount, false);
};

}  // namespace underwater_stereo
