// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Step 5 of the pipeline: which 3D shape an object's points and outline describe, and its size.
///
/// The stereo points only cover the visible face and are noisy at range; the 2D outline is sharp to a
/// pixel. Each model therefore takes its orientation and depth from the points and its extent from the
/// outline's viewing rays where it can (sphere: the silhouette cone; plane and cylinder: the outline
/// back-projected onto the fitted surface).

#include <Eigen/Geometry>

#include <memory>
#include <string>
#include <vector>

#include "underwater_stereo/detection/shape_features.h"
#include "underwater_stereo/detection/shape_kind.h"
#include "underwater_stereo/detection/shape_model.h"

namespace underwater_stereo {

struct ShapeFitConfig {
  double min_points = 30;           ///< fewer points: ShapeKind::kUnknown
  double plane_preference = 2.5;    ///< margin by which the model the outline does not favour must win
  double min_elongation = 2.2;      ///< outline length/width from which an object may be a cylinder
  double box_face_contrast = 20.0;  ///< an object whose shading splits this clearly into flat faces is a box
  /// The learnt shape decision (the YAML's shape.model_file, loaded); without it the hand-made rules above decide.
  std::shared_ptr<const ShapeModel> model;
  std::string model_file;  ///< where `model` was loaded from (for messages)

  std::vector<std::string> validate() const;
};

struct ShapeFit {
  ShapeKind shape = ShapeKind::kUnknown;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();                 ///< [m] left optical frame
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< object z: cylinder axis / plane normal
  Eigen::Vector3d size = Eigen::Vector3d::Zero();                   ///< [m] as DetectedObject.size
  double rmse_m = 0.0;                                              ///< of the points about the model
  /// [m] box: how far its centre was put behind the visible face, along the line of sight, for the depth it
  /// hides (seen face-on); the silhouette lies that much in front of the centre.
  double hidden_depth_m = 0.0;
  std::vector<float> features;  ///< kShapeFeatureCount values the shape was (or could be) decided from; empty: too few points
};

/// Fits the object. `points`: its cluster (left optical frame, metres); `outline_rays`: unit viewing rays
/// of its 2D contour (left optical frame, lens distortion removed); `cues`: its outline and shading. With a
/// shape model (config.model) the model names the shape from the cues and the fits' evidence together;
/// without one, the outline settles close calls between plane and sphere, and flat faces of clearly different
/// shading make a box (stereo on uniformly coloured faces is too smooth to show their edges). A box or
/// cylinder is centred at its centre, not on its visible face. Returns ShapeKind::kUnknown with the points'
/// centroid and extents when no model fits.
ShapeFit fitShape(const std::vector<Eigen::Vector3f>& points, const std::vector<Eigen::Vector3d>& outline_rays,
                  const OutlineCues& cues, const ShapeFitConfig& config);

/// The cylinder fitShape reports for points it names a cylinder: along the points' main axis once they are moved
/// along their rays onto the plane fitted to them in disparity (their depth noise taken out), its diameter and
/// length from the outline, its centre a radius behind the visible surface and midway along the points on the
/// axis. ShapeKind::kUnknown for fewer than 3 points or when the outline does not reach the plane through the axis.
ShapeFit fitCylinder(const std::vector<Eigen::Vector3f>& points, const std::vector<Eigen::Vector3d>& outline_rays);

}  // namespace underwater_stereo
