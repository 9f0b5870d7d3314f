// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The command-line options that set a scene sampler (render_scene --random, evaluate_detector --random).

#include <stdexcept>
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

  static bool takes(const std::string& option) { return find(option) != nullptr; }

  /// Reads `value` of `option` into `sampler`; "" or why it is not of the option's form.
  /// @throw std::invalid_argument for an option takes() does not accept.
  std::string read(const std::string& option, const std::string& value, sim::SceneSamplerConfig& sampler) {
    const Option* o = find(option);
    if (o == nullptr) throw std::invalid_argument("SamplerOptions: no option " + option);
    this->*o->kept = value;
    const bool parsed = o->range == nullptr ? parseImageSize(value, sampler.width, sampler.height)
                                            : parseInterval(value, sampler.*o->range);
    return parsed ? "" : option + ": '" + value + "' is not " + o->form;
  }

  /// Every option given, as a command line would repeat it (" --size 960x600 --luma 12,40"; "" when none).
  std::string given() const {
    std::string out;
    for (const Option& o : options()) {
      if (!(this->*o.kept).empty()) out += std::string(" ") + o.name + " " + this->*o.kept;
    }
    return out;
  }

  /// The first of `sampler`'s problems named as the option that set it ("--luma 0,40: target_luma = ..."; the
  /// image size's for any problem no other option's sampler field begins: only these options set the sampler);
  /// "" when none.
  std::string problem(const sim::SceneSamplerConfig& sampler) const {
    const std::vector<std::string> problems = sampler.validate();
    if (problems.empty()) return "";
    const std::string& p = problems.front();
    const Option* by = &options().front();  // --size
    for (const Option& o : options()) {
      if (o.field != nullptr && p.rfind(o.field, 0) == 0) by = &o;
    }
    return std::string(by->name) + " " + this->*by->kept + ": " + p;
  }

  /// The head that renders `scene` of `sampler`: `shared` (its pixel rays reused) when the sampler's optics are
  /// fixed, else one of the scene's own rig.
  static sim::Renderer headFor(const sim::SceneSamplerConfig& sampler, const sim::Renderer& shared, const sim::Scene& scene) {
    return sampler.variesOptics() ? sim::Renderer(scene) : shared.withScene(scene);
  }

 private:
  /// One option: its name and form, where its value is kept as given, the sampler's range it sets and the field
  /// its problems begin with (nullptr for the image size, which sets width and height).
  struct Option {
    const char* name;
    const char* form;
    std::string SamplerOptions::*kept;
    std::pair<double, double> sim::SceneSamplerConfig::*range;
    const char* field;
  };

  static const std::vector<Option>& options() {
    static const std::vector<Option> table{
        {"--size", "WIDTHxHEIGHT", &SamplerOptions::size, nullptr, nullptr},
        {"--luma", "LO,HI", &SamplerOptions::luma, &sim::SceneSamplerConfig::target_luma, "target_luma"},
        {"--focal-mm", "LO,HI", &SamplerOptions::focal, &sim::SceneSamplerConfig::focal_length_mm, "focal_length_mm"},
        {"--baseline-m", "LO,HI", &SamplerOptions::baseline, &sim::SceneSamplerConfig::baseline_m, "baseline_m"}};
    return table;
  }

  static const Option* find(const std::string& option) {
    for (const Option& o : options()) {
      if (option == o.name) return &o;
    }
    return nullptr;
  }
};

}  // namespace tools
}  // namespace underwater_stereo
