// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/shape_kind.h"

#include <array>
#include <stdexcept>
#include <utility>

namespace underwater_stereo {
namespace {

/// Every shape once, with its name: both directions of the conversion read this one list.
constexpr std::array<std::pair<ShapeKind, const char*>, 5> kShapeNames{{{ShapeKind::kSphere, "sphere"},
                                                                        {ShapeKind::kCylinder, "cylinder"},
                                                                        {ShapeKind::kBox, "box"},
                                                                        {ShapeKind::kPlane, "plane"},
                                                                        {ShapeKind::kUnknown, "unknown"}}};

}  // namespace

const char* shapeName(ShapeKind shape) {
  for (const auto& [kind, name] : kShapeNames) {
    if (kind == shape) return name;
  }
  return "";  // not reached: the table lists every shape (shape_kind_test)
}

ShapeKind shapeFromName(const std::string& name, const std::string& field) {
  std::string allowed;
  for (const auto& [kind, n] : kShapeNames) {
    if (name == n) return kind;
    allowed += (allowed.empty() ? "" : ", ") + std::string(n);
  }
  throw std::invalid_argument(field + ": '" + name + "' is not one of " + allowed);
}

bool shapesAgree(ShapeKind a, ShapeKind b) { return a == b || a == ShapeKind::kUnknown || b == ShapeKind::kUnknown; }

std::ostream& operator<<(std::ostream& out, ShapeKind shape) { return out << shapeName(shape); }

}  // namespace underwater_stereo
