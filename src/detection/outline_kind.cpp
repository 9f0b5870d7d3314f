// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/outline_kind.h"

namespace underwater_stereo {

const char* outlineName(OutlineKind outline) {
  switch (outline) {
    case OutlineKind::kCircle: return "circle";
    case OutlineKind::kEllipse: return "ellipse";
    case OutlineKind::kTriangle: return "triangle";
    case OutlineKind::kRectangle: return "rectangle";
    case OutlineKind::kPolygon: return "polygon";
  }
  return "";  // not reached: the switch names every outline (-Wswitch)
}

std::ostream& operator<<(std::ostream& out, OutlineKind outline) { return out << outlineName(outline); }

}  // namespace underwater_stereo
