// SPDX-License-Identifier: BSD-3-Clause
// evaluate_detector's brightness sweep end to end: its options are checked before anything is rendered, and a sweep
// over scenes ends with one row per level.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>

#include <unistd.h>

#include "tool_test_helpers.h"

namespace fs = std::filesystem;
using namespace underwater_stereo;

namespace {

const std::string kEvaluate = std::string(UWS_EVALUATE_DETECTOR) + " --config " UWS_SOURCE_DIR "/config/detector.yaml";

fs::path logFile(const std::string& name) {
  return fs::temp_directory_path() / ("evaluate_detector_test_" + std::to_string(::getpid()) + "_" + name + ".log");
}

}  // namespace

TEST(EvaluateDetector, BadLevelsOrScenesAreNamedAndNothingIsRendered) {
  const struct {
    std::string options, named;
  } cases[] = {{"--paper-brightness --levels 18,x", "'x' is not a mean luma"},
               {"--paper-brightness --levels 300", "'300' is not a mean luma"},
               {"--paper-brightness --levels 18,", "is not a list of lumas"},
               {"--paper-brightness --scenes 0", "--scenes: '0'"},
               {"--random 2 --levels 18", "go with --paper-brightness"}};
  for (const auto& c : cases) {
    const fs::path log = logFile("bad");
    EXPECT_EQ(runTool(kEvaluate + " " + c.options, log), 2) << c.options;
    const std::string text = readText(log);
    EXPECT_NE(text.find(c.named), std::string::npos) << c.options << ": " << text;
    EXPECT_EQ(text.find("Scene of seed"), std::string::npos) << c.options;
    fs::remove(log);
  }
}

// Two scenes at luma 18, under the paper's gate (20): the shipped configuration searches them (none spoiled).
TEST(EvaluateDetector, SweepOverScenesEndsWithARowPerLevel) {
  const fs::path log = logFile("sweep");
  ASSERT_EQ(runTool(kEvaluate + " --paper-brightness --seed 1181 --scenes 2 --levels 18 --size 640x400", log), 0)
      << readText(log);
  const std::string text = readText(log);
  EXPECT_NE(text.find("Scene of seed 1181 "), std::string::npos) << text;
  EXPECT_NE(text.find("Scene of seed 1182 "), std::string::npos) << text;
  const std::size_t summary = text.find("Scenes of seeds 1181-1182");
  ASSERT_NE(summary, std::string::npos) << text;
  const std::size_t row = text.find("| 18.0 | ", summary);
  ASSERT_NE(row, std::string::npos) << text;
  std::istringstream cells(text.substr(row + 9));
  int frames = -1, not_reached = -1, spoiled = -1;
  char bar = 0;
  cells >> frames >> bar >> not_reached >> bar >> spoiled;
  EXPECT_EQ(frames + not_reached, 2) << text;
  EXPECT_GE(frames, 1) << text;
  EXPECT_EQ(spoiled, 0) << text;
  fs::remove(log);
}
