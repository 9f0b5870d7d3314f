// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The detector judged at set brightness levels (evaluate_detector --paper-brightness): a sampled scene rendered at
// each level's mean luma, one table per scene, and over several scenes recall and false detections per level.
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "underwater_stereo/detection/detector_config.h"
#include "underwater_stereo/sim/scene_sampler.h"

namespace underwater_stereo {
namespace tools {

/// Mean luma of the paper's eight brightness levels (Kramar et al. 2023, Fig. 20/21).
extern const std::vector<double> kPaperLevels;

/// The levels of `text` ("L,L,.."), each a mean luma in (0, 255).
/// @throw std::invalid_argument naming the item or, when an item is empty, the whole list.
std::vector<double> parseLevels(const std::string& text);

/// The scenes of seeds seed..seed+scenes-1 at each of `levels` (the exposure scaled until the left image's mean
/// BT.601 luma, as the camera delivers it, is within 1 of the level; then one detection), a table per scene into
/// `out`; with `summary`, then per level over the frames that reached it: frames, those not reached, spoiled ones,
/// objects, found, recall and false detections per frame.
void sweepBrightness(std::ostream& out, const DetectorConfig& config, const sim::SceneSamplerConfig& sampler,
                     std::uint64_t seed, int scenes, const std::vector<double>& levels, bool summary);

}  // namespace tools
}  // namespace underwater_stereo
