// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Small scenes for the simulator tests.
#include "underwater_stereo/sim/scene.h"

namespace underwater_stereo {
namespace sim {
namespace test {

/// 640x400 head with the real head's field of view, no noise, one object.
inline Scene smallScene(const SceneObject& object) {
  Scene s;
  s.rig.width = 640;
  s.rig.height = 400;
  s.rig.pixel_size_um = 5.86 * 3.0;
  s.sensor.noise_sigma = 0.0;
  s.sensor.encoding = "bgr8";
  s.objects.push_back(object);
  return s;
}

inline SceneObject sphere(const std::string& name, const Eigen::Vector3d& position, double diameter) {
  SceneObject o;
  o.name = name;
  o.shape = ShapeType::kSphere;
  o.colour = "red";
  o.position_m = position;
  o.size_m = Eigen::Vector3d::Constant(diameter);
  return o;
}

}  // namespace test
}  // namespace sim
}  // namespace underwater_stereo
