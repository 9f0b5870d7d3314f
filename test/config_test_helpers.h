// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// What the detection tests share about refused configurations.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>
#include <string>

#include "underwater_stereo/detection/detector_config.h"

namespace underwater_stereo {

/// What parseDetectorConfig says when it refuses `yaml` (model files in the test's temporary folder); empty when
/// it accepts it.
inline std::string refusalOf(const std::string& yaml) {
  try {
    parseDetectorConfig(YAML::Load(yaml), ::testing::TempDir());
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace underwater_stereo
