// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// A check of a whole run of a scene before anything is rendered, for the tools that render scene files (render_scene,
// and through scene_files.h those that run the detector on them). The simulator's alone: no detector in it.
#include <string>
#include <vector>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/sim/renderer.h"

namespace underwater_stereo {
namespace tools {

/// Why `renderer`'s scene, named `named`, cannot be rendered at frames 0 .. frames - 1 at `rate_hz` (a camera inside
/// an object at one of them: it would see only the object's inside); "" when it can.
inline std::string renderProblem(const sim::Renderer& renderer, const std::string& named, int frames, double rate_hz) {
  const std::vector<std::string> inside = renderer.camerasInside(frames, rate_hz);
  return inside.empty() ? "" : joinProblems(named + ": cannot be rendered", inside);
}

}  // namespace tools
}  // namespace underwater_stereo
