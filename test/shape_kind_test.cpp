// SPDX-License-Identifier: BSD-3-Clause
// The shape and outline enums' names: the one place that turns them into text and back.
#include <gtest/gtest.h>

#include <sstream>

#include "underwater_stereo/detection/outline_kind.h"
#include "underwater_stereo/detection/shape_kind.h"

using namespace underwater_stereo;

TEST(ShapeKind, EveryShapeRoundTripsThroughItsName) {
  for (const ShapeKind s :
       {ShapeKind::kUnknown, ShapeKind::kSphere, ShapeKind::kCylinder, ShapeKind::kBox, ShapeKind::kPlane}) {
    EXPECT_EQ(shapeFromName(shapeName(s), "shape"), s) << shapeName(s);
    std::ostringstream printed;
    printed << s;
    EXPECT_EQ(printed.str(), shapeName(s));
  }
  EXPECT_STREQ(shapeName(ShapeKind::kPlane), "plane");
}

TEST(ShapeKind, AnUnknownNameIsRefusedNamingTheFieldAndEveryAllowedName) {
  for (const char* bad : {"cone", "Sphere", "panel", ""}) {
    try {
      shapeFromName(bad, "targets[2].shape");
      ADD_FAILURE() << "'" << bad << "' accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()),
                "targets[2].shape: '" + std::string(bad) + "' is not one of sphere, cylinder, box, plane, unknown");
    }
  }
}

TEST(ShapeKind, UnknownAgreesWithEveryShapeOtherShapesOnlyWithThemselves) {
  EXPECT_TRUE(shapesAgree(ShapeKind::kSphere, ShapeKind::kSphere));
  EXPECT_TRUE(shapesAgree(ShapeKind::kUnknown, ShapeKind::kBox));
  EXPECT_TRUE(shapesAgree(ShapeKind::kPlane, ShapeKind::kUnknown));
  EXPECT_FALSE(shapesAgree(ShapeKind::kSphere, ShapeKind::kCylinder));
}

TEST(OutlineKind, EveryOutlineHasItsOwnName) {
  std::ostringstream printed;
  for (const OutlineKind o : {OutlineKind::kCircle, OutlineKind::kEllipse, OutlineKind::kTriangle,
                              OutlineKind::kRectangle, OutlineKind::kPolygon}) {
    printed << o << " ";
  }
  EXPECT_EQ(printed.str(), "circle ellipse triangle rectangle polygon ");
}
