// SPDX-License-Identifier: BSD-3-Clause
#include "brightness_sweep.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "random_evaluation.h"
#include "tool_helpers.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/detection/raw_frame.h"
#include "underwater_stereo/sim/renderer.h"

namespace underwater_stereo {
namespace tools {

const std::vector<double> kPaperLevels = {242.8, 198.0, 155.0, 112.0, 80.0, 55.0, 33.0, 18.0};

namespace {

/// What the frames at one brightness level gave, over scenes.
struct LevelTally {
  int frames = 0, not_reached = 0, spoiled = 0, eligible = 0, found = 0, false_detections = 0;
};

/// The scene of `seed` at each of `levels` into `out`, each level's frame added to `tallies` (one per level).
void sweepScene(std::ostream& out, const DetectorConfig& config, const sim::SceneSamplerConfig& sampler,
                std::uint64_t seed, const std::vector<double>& levels, std::vector<LevelTally>& tallies) {
  const sim::SampledScene sampled = sim::sampleScene(seed, sampler);
  const sim::Renderer head(sampled.scene);
  const Detector detector(config, head.calibration());
  out << "Scene of seed " << seed << " (turbidity " << std::fixed << std::setprecision(2) << sampled.turbidity
      << ", water type " << sampled.water_type << ") at "
      << (levels == kPaperLevels ? "the paper's brightness levels" : "the brightness levels asked for")
      << "\n\n| target luma | luma | exposure | quality |";
  for (const auto& o : sampled.scene.objects) out << " " << o.name << " |";
  out << "\n|---|---|---|---|";
  for (std::size_t i = 0; i < sampled.scene.objects.size(); ++i) out << "---|";
  out << "\n";
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const double level = levels[k];
    sim::Scene scene = sampled.scene;
    sim::autoExpose(scene, level, 4);
    double lo = 0.0, hi = 1e9, luma = 0.0;
    sim::RenderedPair pair;
    for (int iteration = 0; iteration < 10; ++iteration) {
      pair = head.withScene(scene).render(0.0, 0);
      luma = sim::meanLuma(RawFrame(pair.left, pixelLayoutOf(pair.encoding)).bgr());
      if (std::abs(luma - level) < 1.0) break;
      double& bound = luma < level ? lo : hi;
      bound = scene.light.exposure;
      double next = scene.light.exposure * std::clamp(std::pow(level / std::max(luma, 1.0), scene.sensor.gamma), 0.1, 10.0);
      if (!(next > lo && next < hi)) next = hi < 1e9 && lo > 0.0 ? std::sqrt(lo * hi) : next;
      scene.light.exposure = std::clamp(next, 0.011, 99.0);
    }
    const DetectionResult result = detector.detect(RawFrame(pair.left, pixelLayoutOf(pair.encoding)),
                                                   RawFrame(pair.right, pixelLayoutOf(pair.encoding)));
    const PairRecord record = evaluatePair(sampled, pair, result, luma);
    out << "| " << std::setprecision(1) << level << " | " << luma << " | " << std::setprecision(3)
        << scene.light.exposure << " | " << record.quality << " |";
    for (const auto& o : record.objects) {
      out << " ";
      if (!o.eligible) out << "(not eligible: " << o.visible_pixels << " px, " << std::setprecision(1) << o.range_m << " m)";
      else if (!o.found) out << "missed";
      else {
        out << o.detected_colour << " " << o.detected_shape << ", range err " << std::setprecision(1)
            << 100.0 * o.range_error << " %";
      }
      out << " |";
    }
    out << (record.false_detections.empty() ? "" : " +" + std::to_string(record.false_detections.size()) + " false")
        << "\n";
    LevelTally& t = tallies[k];
    if (std::abs(luma - level) >= 1.0) {
      ++t.not_reached;
      continue;
    }
    ++t.frames;
    t.spoiled += result.quality.spoiled();
    t.false_detections += static_cast<int>(record.false_detections.size());
    for (const auto& o : record.objects) {
      t.eligible += o.eligible;
      t.found += o.eligible && o.found;
    }
  }
}

}  // namespace

std::vector<double> parseLevels(const std::string& text) {
  std::vector<double> levels;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) {
    double level = 0.0;
    if (item.empty()) throw std::invalid_argument("--levels: '" + text + "' has an empty item");
    if (!parseNumber(item, level) || !(level > 0.0 && level < 255.0)) {
      throw std::invalid_argument("--levels: '" + item + "' is not a mean luma in (0, 255)");
    }
    levels.push_back(level);
  }
  if (levels.empty() || text.back() == ',') throw std::invalid_argument("--levels: '" + text + "' has an empty item");
  return levels;
}

void sweepBrightness(std::ostream& out, const DetectorConfig& config, const sim::SceneSamplerConfig& sampler,
                     std::uint64_t seed, int scenes, const std::vector<double>& levels, bool summary) {
  if (scenes < 1 || levels.empty()) throw std::invalid_argument("sweepBrightness: no scene or no level");
  std::vector<LevelTally> tallies(levels.size());
  for (int i = 0; i < scenes; ++i) {
    if (i > 0) out << "\n";
    sweepScene(out, config, sampler, seed + static_cast<std::uint64_t>(i), levels, tallies);
  }
  if (!summary) return;
  out << "\nScenes of seeds " << seed << "-" << seed + static_cast<std::uint64_t>(scenes) - 1
      << ", frames that reached their level (within 1 of its luma)\n\n"
         "| target luma | frames | not reached | spoiled | objects | found | recall % | false/frame |\n"
         "|---|---|---|---|---|---|---|---|\n";
  for (std::size_t k = 0; k < levels.size(); ++k) {
    const LevelTally& t = tallies[k];
    std::ostringstream level;  // as given: 18, 242.8
    level << levels[k];
    out << "| " << level.str() << " | " << t.frames << " | " << t.not_reached << " | " << t.spoiled
        << " | " << t.eligible << " | " << t.found << " | " << ratioCell(t.found, t.eligible, 100.0, 1) << " | "
        << ratioCell(t.false_detections, t.frames, 1.0, 2) << " |\n";
  }
}

}  // namespace tools
}  // namespace underwater_stereo
