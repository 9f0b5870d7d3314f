// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Scene files for a tool that runs the detector on them: every one read, made ready to render and its rig tried on the
// detector, before anything is rendered or timed, so that a bad one is named at once (not after the scenes before it).
#include <exception>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "render_problem.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/sim/renderer.h"
#include "underwater_stereo/sim/scene.h"

namespace underwater_stereo {
namespace tools {

/// Why `scene`, named `named`, cannot be rendered (a camera inside an object, at time 0 or at one of `frames` frames
/// at `rate_hz`: renderProblem) or the detector with `config` refuses its rig (image size, baseline); "" when neither.
inline std::string sceneProblem(const DetectorConfig& config, const sim::Scene& scene, const std::string& named,
                                int frames, double rate_hz) {
  std::optional<sim::Renderer> renderer;
  try {
    renderer.emplace(scene);
  } catch (const std::invalid_argument& e) {
    return named + ": " + e.what();
  }
  if (std::string problem = renderProblem(*renderer, named, frames, rate_hz); !problem.empty()) return problem;
  try {
    const Detector detector(config, renderer->calibration());
  } catch (const std::exception& e) {
    return named + ": the detector refuses its rig: " + e.what();
  }
  return "";
}

/// The scene files at `paths` that can be read; each that cannot, cannot be rendered at one of `frames` frames at
/// `rate_hz`, or whose rig the detector with `config` refuses (the last two not tried when `config` is null: the
/// configuration could not be read), is added to `problems`.
inline std::vector<std::pair<std::string, sim::Scene>> readSceneFiles(const std::vector<std::string>& paths,
                                                                      const DetectorConfig* config, int frames,
                                                                      double rate_hz, std::vector<std::string>& problems) {
  std::vector<std::pair<std::string, sim::Scene>> scenes;
  for (const std::string& path : paths) {
    try {
      scenes.emplace_back(path, sim::loadSceneFile(path));
    } catch (const std::exception& e) {
      problems.push_back(e.what());
      continue;
    }
    if (config == nullptr) continue;
    if (std::string problem = sceneProblem(*config, scenes.back().second, path, frames, rate_hz);
        !problem.empty()) {
      problems.push_back(std::move(problem));
    }
  }
  return scenes;
}

}  // namespace tools
}  // namespace underwater_stereo
