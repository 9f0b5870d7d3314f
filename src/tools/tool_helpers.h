// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Small pieces the command-line tools share.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace underwater_stereo {
namespace tools {

/// `text` as a number into `out`: false (out untouched) unless the whole of it is one, leading blanks allowed.
inline bool parseNumber(const std::string& text, double& out) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || *end != '\0') return false;
  out = v;
  return true;
}

/// `value` with `digits` decimals, as a table cell.
inline std::string fixedCell(double value, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << value;
  return s.str();
}

/// `part` / `whole` times `scale` (100: a percentage) with `digits` decimals, as a table cell; "-" when `whole` is 0.
inline std::string ratioCell(double part, int whole, double scale, int digits) {
  return whole <= 0 ? "-" : fixedCell(scale * part / whole, digits);
}

/// The q-quantile (0..1, nearest rank) of `v`; NaN when empty.
inline double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

/// The q-quantile of `v` times `scale` as a table cell of `digits` decimals, "-" when `v` is empty.
inline std::string percentileCell(const std::vector<double>& v, double q, double scale, int digits) {
  return v.empty() ? "-" : fixedCell(scale * percentile(v, q), digits);
}

/// The JSON records evaluate_detector --random --json wrote to `path` (what learn_shapes and learn_checks learn from).
/// @throw std::invalid_argument naming the file when it is not readable, holds no "pairs" list or was made with
/// --swapped.
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
  if (root["config"] && root["config"].as<std::string>("").find(" --swapped") != std::string::npos) {
    throw std::invalid_argument(path + ": made with --swapped (pairs given the wrong way round): nothing to learn from");
  }
  return root;
}

/// Reads a learning tool's command line: --help, the options in `values` (each takes one value, e.g. "--out"), and
/// the records files. @return -1 to go on, or the exit code to leave with (0 after --help, 2 after an unknown option
/// or an option without its value), with the usage printed.
inline int parseRecordsCommandLine(int argc, char** argv, const std::string& tool, const char* usage,
                                   std::map<std::string, std::string>& values, std::vector<std::string>& inputs) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::cout << usage;
      return 0;
    }
    if (values.count(a) != 0 && i + 1 < argc) {
      values[a] = argv[++i];
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << tool << ": unknown option or option without its value: " << a << "\n" << usage;
      return 2;
    } else {
      inputs.push_back(a);
    }
  }
  return -1;
}

}  // namespace tools
}  // namespace underwater_stereo
