// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The command-line options that set a scene sampler (render_scene --random, evaluate_detector --random).

#include <string>
#include <vector>

#include "tool_helpers.h"
#include "underwater_stereo/sim/scene_sampler.h"

namespace underwater_stereo {
namespace tools {

/// --size WxH and --luma LO,HI, read strictly and kept as given, so that a value the sampler refuses is named by the
/// option that set it.
struct SamplerOptions {
  std::string size, luma;  ///< as given ("" when not given)

  static bool takes(const std::string& option) { return option == "--size" || option == "--luma"; }

  /// Reads `value` of `option` (one that takes() accepts) into `sampler`; "" or why it is not of the option's form.
  std::string read(const std::string& option, const std::string& value, sim::SceneSamplerConfig& sampler) {
    if (option == "--size") {
      size = value;
      return parseImageSize(value, sampler.width, sampler.height) ? "" : "--size: '" + value + "' is not WIDTHxHEIGHT";
    }
    luma = value;
    return parseInterval(value, sampler.target_luma) ? "" : "--luma: '" + value + "' is not LO,HI";
  }

  /// The first of `sampler`'s problems named as the option that set it ("--luma LO,HI: ..." for the target luma,
  /// "--size WxH: ..." otherwise: only these options set the sampler); "" when none.
  std::string problem(const sim::SceneSamplerConfig& sampler) const {
    const std::vector<std::string> problems = sampler.validate();
    if (problems.empty()) return "";
    const std::string& p = problems.front();
    return (p.rfind("target_luma", 0) == 0 ? "--luma " + luma : "--size " + size) + ": " + p;
  }
};

}  // namespace tools
}  // namespace underwater_stereo
