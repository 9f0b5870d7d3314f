// SPDX-License-Identifier: BSD-3-Clause
// detectorTunables(): the table's ranges are what DetectorConfig::validate() accepts (each end accepted, one
// step beyond refused naming the key and quoting the range), and every row is read from YAML into its own field.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <opencv2/core.hpp>

#include <cmath>
#include <map>
#include <string>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/detection/detector_config.h"

using namespace underwater_stereo;

namespace {

/// Ordered pairs (lower < upper is required): probing one end of one, the other is put at its far end.
const std::map<std::string, std::string> kUpperOf = {{"quality.too_dark_below", "quality.too_bright_above"},
                                                     {"quality.dark_pixel_value", "quality.bright_pixel_value"},
                                                     {"candidates.min_area_px", "candidates.max_area_px"},
                                                     {"stereo.min_depth_m", "stereo.max_depth_m"}};

const DetectorTunable& tunable(const std::string& name) {
  for (const DetectorTunable& t : detectorTunables()) {
    if (t.name() == name) return t;
  }
  throw std::invalid_argument("no tunable " + name);
}

/// The default configuration with one designated colour (it needs one).
DetectorConfig base() {
  DetectorConfig c;
  ColourClass red;
  red.name = "red";
  red.hue_min = 170;
  red.hue_max = 10;
  c.colours.classes.push_back(red);
  return c;
}

/// base() with `t` at `value` and its partner (if any) out of the way.
DetectorConfig with(const DetectorTunable& t, double value) {
  DetectorConfig c = base();
  for (const auto& [lower, upper] : kUpperOf) {
    if (t.name() == lower) tunable(upper).set(c, tunable(upper).max);
    if (t.name() == upper) tunable(lower).set(c, tunable(lower).min);
  }
  t.set(c, value);
  return c;
}

bool names(const std::vector<std::string>& problems, const DetectorTunable& t) {
  for (const std::string& p : problems) {
    if (p.find(t.key) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

TEST(DetectorTunables, EachEndIsAcceptedAndOneStepBeyondRefused) {
  ASSERT_GE(detectorTunables().size(), 25u);
  for (const DetectorTunable& t : detectorTunables()) {
    ASSERT_TRUE((t.real == nullptr) != (t.integer == nullptr)) << t.name();
    ASSERT_LT(t.min, t.max) << t.name();
    const double step = t.integer ? 1.0 : std::max(1e-9, 1e-6 * std::max(std::abs(t.min), std::abs(t.max)));
    for (const double end : {t.min, t.max}) {
      const auto problems = with(t, end).validate();
      EXPECT_TRUE(problems.empty()) << t.name() << " = " << end << " (an end of its range) refused: "
                                    << joinProblems("", problems);
    }
    // Refused quoting the table's range in every range message that names it (a component's own check quoting
    // another range would send the user from one message to the next); a pair's order is a message of its own.
    const auto text = [](double v, const char* format) { return cv::format(format, v); };
    const std::string range = "[" + text(t.min, "%g") + ", " + text(t.max, "%g") + "]",  // or written out whole
        whole = "[" + text(t.min, t.min == std::floor(t.min) ? "%.0f" : "%g") + ", " +
                text(t.max, t.max == std::floor(t.max) ? "%.0f" : "%g") + "]";
    for (const double beyond : {t.min - step, t.max + step, t.min - 0.5 * (t.max - t.min), t.max + (t.max - t.min)}) {
      const auto problems = with(t, beyond).validate();
      EXPECT_TRUE(names(problems, t)) << t.name() << " = " << beyond << " (beyond its range) accepted";
      for (const std::string& p : problems) {
        if (p.find(t.key) != std::string::npos && p.find("must be in") != std::string::npos) {
          EXPECT_TRUE(p.find(range) != std::string::npos || p.find(whole) != std::string::npos) << t.name() << ": " << p;
        }
      }
    }
  }
}

TEST(DetectorTunables, EveryRowIsReadFromYamlIntoItsField) {
  for (const DetectorTunable& t : detectorTunables()) {
    // Inside the range, not a default; odd-only ints (odd minimum) stay odd.
    const double value = t.integer ? t.min + 2 : (3 * t.min + t.max) / 4;
    YAML::Node root = YAML::Load("colours: [{name: red, hue: [170, 10]}]");
    if (*t.section) {
      root[t.section][t.key] = value;
    } else {
      root[t.key] = value;
    }
    for (const auto& [lower, upper] : kUpperOf) {  // keep ordered pairs valid
      if (t.name() == lower) root[tunable(upper).section][tunable(upper).key] = tunable(upper).max;
      if (t.name() == upper) root[tunable(lower).section][tunable(lower).key] = tunable(lower).min;
    }
    DetectorConfig c;
    try {
      c = parseDetectorConfig(root);
    } catch (const std::invalid_argument& e) {
      ADD_FAILURE() << t.name() << " = " << value << ": " << e.what();
      continue;
    }
    EXPECT_EQ(t.get(c), value) << t.name();
  }
}

TEST(DetectorTunables, AnUnknownKeyInATableSectionIsNamedWithTheKnownOnes) {
  const YAML::Node root = YAML::Load("stereo: {min_depth: 0.5}\ncluster: {eps_m: 0.05}");
  try {
    parseDetectorConfig(root);
    FAIL() << "accepted stereo.min_depth";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("stereo.min_depth: unknown key (known: min_depth_m, max_depth_m"), std::string::npos) << what;
  }
}
