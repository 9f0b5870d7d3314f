// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The command-line options that set a scene sampler (render_scene --random, evaluate_detector --random).

#include <string>
#include <vector>

#include "tool_helpers.h"
#include "underwater_stereo/sim/renderer.h"
#include "underwater_stereo/sim/scene_sampler.h"

namespace underwater_stereo {
namespace tools {

/// --size WxH, --luma LO,HI, --focal-mm LO,HI and --baseline-m LO,HI, read strictly and kept as given, so that a
/// value the sampler refuses is named by the option that set it.
struct SamplerOptions {
  std::string size, luma, focal, baseline;  ///< as given ("" when not given)

  static bool takes(const std::string& option) {
    return option == "--size" || option == "--luma" || option == "--focal-mm" || option == "--baseline-m";
  }

  /// Reads `value` of `option` (one that takes() accepts) into `sampler`; "" or why it is not of the option's form.
  std::string read(const std::string& option, const std::string& value, sim::SceneSamplerConfig& sampler) {
    if (option == "--size") {
      size = value;
      return parseImageSize(value, sampler.width, sampler.height) ? "" : "--size: '" + value + "' is not WIDTHxHEIGHT";
    }
    auto [given, range] = interval(option, sampler);
    *given = value;
    return parseInterval(value, *range) ? "" : option + ": '" + value + "' is not LO,HI";
  }

  /// Every option given, as a command line would repeat it (" --size 960x600 --luma 12,40"; "" when none).
  std::string given() const {
    std::string out;
    for (const auto& [option, value] : {std::pair<const char*, const std::string*>{"--size", &size}, {"--luma", &luma},
                                        {"--focal-mm", &focal}, {"--baseline-m", &baseline}}) {
      if (!value->empty()) out += std::string(" ") + option + " " + *value;
    }
    return out;
  }

  /// The first of `sampler`'s problems named as the option that set it ("--luma LO,HI: ..." for the target luma,
  /// "--focal-mm LO,HI: ..." and "--baseline-m LO,HI: ..." for the optics, "--size WxH: ..." for the image size:
  /// only these options set the sampler); "" when none.
  std::string problem(const sim::SceneSamplerConfig& sampler) const {
    const std::vector<std::string> problems = sampler.validate();
    if (problems.empty()) return "";
    const std::string& p = problems.front();
    auto starts = [&p](const char* field) { return p.rfind(field, 0) == 0; };
    const std::string named = starts("target_luma")       ? "--luma " + luma
                              : starts("focal_length_mm") ? "--focal-mm " + focal
                              : starts("baseline_m")      ? "--baseline-m " + baseline
                                                          : "--size " + size;
    return named + ": " + p;
  }

  /// The head that renders `scene` of `sampler`: `shared` (its pixel rays reused) when the sampler's optics are
  /// fixed, else one of the scene's own rig.
  static sim::Renderer headFor(const sim::SceneSamplerConfig& sampler, const sim::Renderer& shared, const sim::Scene& scene) {
    return sampler.variesOptics() ? sim::Renderer(scene) : shared.withScene(scene);
  }

 private:
  /// Where an interval option is kept as given, and the sampler's range it sets.
  std::pair<std::string*, std::pair<double, double>*> interval(const std::string& option, sim::SceneSamplerConfig& sampler) {
    if (option == "--luma") return {&luma, &sampler.target_luma};
    if (option == "--focal-mm") return {&focal, &sampler.focal_length_mm};
    return {&baseline, &sampler.baseline_m};
  }
};

}  // namespace tools
}  // namespace underwater_stereo
