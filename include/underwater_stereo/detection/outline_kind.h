// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The classes of a 2D contour (classifyOutline), and their names at the boundaries (DetectedObject's
/// OUTLINE_* constants, JSON, printed text). Nothing else in the core handles outline names.

#include <ostream>

namespace underwater_stereo {

enum class OutlineKind {
  kCircle,
  kEllipse,
  kTriangle,
  kRectangle,
  kPolygon,  ///< none of the others
};

/// "circle", "ellipse", "triangle", "rectangle" or "polygon" (as DetectedObject::OUTLINE_*).
const char* outlineName(OutlineKind outline);

/// Writes outlineName(outline).
std::ostream& operator<<(std::ostream& out, OutlineKind outline);

}  // namespace underwater_stereo
