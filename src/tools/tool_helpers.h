// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Small pieces the command-line tools share.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace underwater_stereo {
namespace tools {

/// The q-quantile (0..1, nearest rank) of `v`; NaN when empty.
inline double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

/// The JSON records evaluate_detector --random --json wrote to `path` (what learn_shapes and learn_checks learn from).
/// @throw std::invalid_argument naming the file when it is not readable or holds no "pairs" list.
inline YAML::Node loadRandomRecords(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);  // JSON is YAML
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(path + ": not readable as JSON (" + e.what() + ")");
  }
  if (!root.IsMap() || !root["pairs"] || !root["pairs"].IsSequence()) {
    throw std::invalid_argument(path + ": no \"pairs\" list (not evaluate_detector --random --json records)");
  }
  return root;
}

}  // namespace tools
}  // namespace underwater_stereo
