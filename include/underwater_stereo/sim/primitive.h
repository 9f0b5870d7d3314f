// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A scene object placed in the world at one instant, with ray intersection.

#include <Eigen/Core>

#include "underwater_stereo/sim/scene.h"

namespace underwater_stereo {
namespace sim {

/// Where a ray meets a surface.
struct Hit {
  float t = 0.0F;             ///< [m] distance along the (unit) ray
  Eigen::Vector3f normal;     ///< unit outward normal, world frame
  Eigen::Vector3f local;      ///< hit point in the object's frame (for texture that moves with the object)
};

/// One object at one instant: its pose in the world and its shape in its own frame.
class Primitive {
 public:
  /// `rotation` maps object-frame vectors to the world; `size_m` as SceneObject::size_m.
  Primitive(ShapeType shape, const Eigen::Vector3f& centre, const Eigen::Matrix3f& rotation,
            const Eigen::Vector3f& size_m);

  /// Nearest intersection of the ray origin + t * dir (dir unit, world) with t in (0, t_max).
  bool intersect(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float t_max, Hit& hit) const;
  /// Whether `point` (world) lies inside the object (a panel has no inside).
  bool contains(const Eigen::Vector3f& point) const;

 private:
  bool intersectSphere(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max, float& t,
                       Eigen::Vector3f& n) const;
  bool intersectCylinder(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max, float& t,
                         Eigen::Vector3f& n) const;
  bool intersectBox(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max, float& t,
                    Eigen::Vector3f& n) const;
  bool intersectPanel(const Eigen::Vector3f& o, const Eigen::Vector3f& d, float t_max, float& t,
                      Eigen::Vector3f& n) const;

  ShapeType shape_;
  Eigen::Vector3f centre_;
  Eigen::Matrix3f rotation_;   ///< object -> world
  Eigen::Vector3f half_;       ///< half extents in the object frame (sphere: radius in x)
  float bound_radius_sq_;      ///< squared radius of a sphere around the centre that holds the whole object
};

}  // namespace sim
}  // namespace underwater_stereo
