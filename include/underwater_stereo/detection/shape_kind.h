// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The 3D shapes the detector tells apart, and their names at the boundaries (DetectedObject's SHAPE_*
/// constants, JSON, configuration files, printed text). Nothing else in the core handles shape names.

#include <ostream>
#include <string>

namespace underwater_stereo {

enum class ShapeKind {
  kUnknown,   ///< no model fits (too few points, or none explains them)
  kSphere,
  kCylinder,
  kBox,
  kPlane,     ///< a flat panel
};

/// "sphere", "cylinder", "box", "plane" or "unknown" (as DetectedObject::SHAPE_*).
const char* shapeName(ShapeKind shape);

/// The shape called `name` (one of shapeName's). @throw std::invalid_argument naming `field`, the name and
/// every allowed name when `name` is none of them.
ShapeKind shapeFromName(const std::string& name, const std::string& field);

/// Whether detections of shapes `a` and `b` may be one object: the same shape, or either unknown.
bool shapesAgree(ShapeKind a, ShapeKind b);

/// Writes shapeName(shape).
std::ostream& operator<<(std::ostream& out, ShapeKind shape);

}  // namespace underwater_stereo
