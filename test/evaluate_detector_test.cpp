// SPDX-License-Identifier: BSD-3-Clause
// evaluate_detector's brightness sweep end to end: its options are checked before anything is rendered, and a sweep
// over scenes ends with one row per level that sums the scenes' own rows; scene objects it counts as distractors are
// named.
#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "tool_test_helpers.h"

namespace fs = std::filesystem;
using namespace underwater_stereo;

namespace {

const std::string kEvaluate = std::string(UWS_EVALUATE_DETECTOR) + " --config " UWS_SOURCE_DIR "/config/detector.yaml";

fs::path logFile(const std::string& name) {
  return fs::temp_directory_path() / ("evaluate_detector_test_" + std::to_string(::getpid()) + "_" + name + ".log");
}

/// The cells of a Markdown table row ("| a | b | +1 false" -> {"a", "b"}: what follows the last bar is no cell).
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::stringstream s(row.substr(0, row.rfind('|') == std::string::npos ? 0 : row.rfind('|')));
  std::string cell;
  std::getline(s, cell, '|');  // before the first bar
  while (std::getline(s, cell, '|')) {
    const std::size_t a = cell.find_first_not_of(' '), b = cell.find_last_not_of(' ');
    out.push_back(a == std::string::npos ? "" : cell.substr(a, b - a + 1));
  }
  return out;
}

/// What a level's rows of the scenes' own tables say, summed.
struct Counted {
  int frames = 0, objects = 0, found = 0;
};

}  // namespace

TEST(EvaluateDetector, BadOptionsAreNamedAndNothingIsRendered) {
  const struct {
    std::string options, named;
  } cases[] = {{"--paper-brightness --levels 18,x", "'x' is not a mean luma"},
               {"--paper-brightness --levels 300", "'300' is not a mean luma"},
               {"--paper-brightness --levels 0", "'0' is not a mean luma"},
               {"--paper-brightness --levels 18,", "'18,' has an empty item"},
               {"--paper-brightness --levels ,18", "',18' has an empty item"},
               {"--paper-brightness --levels ''", "'' has an empty item"},
               {"--paper-brightness --scenes 0", "--scenes: '0'"},
               {"--random 2 --levels 18", "--levels goes with --paper-brightness, not with --random"},
               {"--random 2 --scenes 2", "--scenes goes with --paper-brightness, not with --random"},
               // An option of another mode is refused, not ignored.
               {"--random 2 --frames 3", "--frames goes with scene files, not with --random"},
               {"--paper-brightness --jobs 2", "--jobs goes with --random, not with --paper-brightness"},
               {"--paper-brightness --verbose", "--verbose goes with scene files or --random, not with"},
               {"scene.yaml --seed 3", "--seed goes with --random or --paper-brightness, not with scene files"},
               {"scene.yaml --size 640x400", "--size goes with --random or --paper-brightness, not with scene"},
               {"--random 2 --size 10x10", "--size 10x10: width"},
               {"--random 2 --size 640x400x3", "--size: '640x400x3' is not WIDTHxHEIGHT"},
               {"--random 2 --size 4294967936x400", "--size: '4294967936x400' is not WIDTHxHEIGHT"},
               {"--random 2 --luma 40,12", "--luma 40,12: target_luma"},
               {"--random 2 --luma 12", "--luma: '12' is not LO,HI"},
               {"--paper-brightness --luma 12,40", "--luma goes with --random, not with --paper-brightness"},
               {"--random 2 --focal-mm 12,4", "--focal-mm 12,4: focal_length_mm"},
               {"--random 2 --baseline-m 0.1", "--baseline-m: '0.1' is not LO,HI"},
               {"--random 2 --baseline-m 0.1,3", "--baseline-m 0.1,3: baseline_m"},
               {"--paper-brightness --focal-mm 4,12", "--focal-mm goes with --random, not with --paper-brightness"},
               {"--random 2 --seed 12abc", "--seed: '12abc' is not a whole number"},
               {"--random 2 --jobs 1.5", "--jobs: '1.5' is not a whole number"},
               {"--random 2 --worst 3 " UWS_SOURCE_DIR "/package.xml", "/package.xml: not a folder that can be made"},
               {"--random 2 --json /nonexistent/records.json", "--json /nonexistent/records.json: its folder"},
               // A rig the simulator renders but the detector refuses: named before anything is rendered.
               {"--random 2 --size 32x32", "the sampled scenes (--size, --focal-mm, --baseline-m): the detector refuses its rig"}};
  for (const auto& c : cases) {
    const fs::path log = logFile("bad");
    EXPECT_EQ(runTool(kEvaluate + " " + c.options, log), 2) << c.options;
    const std::string text = readText(log);
    EXPECT_NE(text.find(c.named), std::string::npos) << c.options << ": " << text;
    EXPECT_EQ(text.find("Scene of seed"), std::string::npos) << c.options;
    fs::remove(log);
  }
}

// Two scenes at luma 18 (under the paper's gate, 20, over the shipped one) and 33: a summary row per level, in the
// order asked for, whose frames, objects and found ones are the sums of the scenes' rows that reached the level.
TEST(EvaluateDetector, SweepOverScenesEndsWithARowPerLevel) {
  const fs::path log = logFile("sweep");
  const int status = runTool(kEvaluate + " --paper-brightness --seed 1181 --scenes 2 --levels 18,33 --size 640x400", log);
  const std::string text = readText(log);
  fs::remove(log);
  ASSERT_EQ(status, 0) << text;
  EXPECT_NE(text.find("Scene of seed 1181 "), std::string::npos) << text;
  EXPECT_NE(text.find("Scene of seed 1182 "), std::string::npos) << text;
  const std::size_t summary = text.find("Scenes of seeds 1181-1182");
  ASSERT_NE(summary, std::string::npos) << text;
  // A table's level rows: those whose first cell is a number (not the header, not the separator).
  auto levelRows = [](const std::string& part) {
    std::vector<std::vector<std::string>> rows;
    std::stringstream lines(part);
    for (std::string line; std::getline(lines, line);) {
      std::vector<std::string> c = cells(line);
      if (c.size() >= 4 && std::isdigit(static_cast<unsigned char>(c[0][0]))) rows.push_back(std::move(c));
    }
    return rows;
  };
  std::map<double, Counted> counted;  // by target level, from the scenes' tables
  for (const auto& c : levelRows(text.substr(0, summary))) {
    const double target = std::stod(c[0]), luma = std::stod(c[1]);
    if (std::abs(luma - target) >= 1.0) continue;  // not reached: counted apart
    EXPECT_EQ(c[3], "OK") << c[0];                 // neither level is spoiled by the shipped gates
    Counted& n = counted[target];
    ++n.frames;
    for (std::size_t k = 4; k < c.size(); ++k) {
      if (c[k].rfind("(not eligible", 0) == 0) continue;
      ++n.objects;
      n.found += c[k] != "missed";
    }
  }
  const std::vector<std::vector<std::string>> summary_rows = levelRows(text.substr(summary));
  ASSERT_EQ(summary_rows.size(), 2U) << text;
  EXPECT_EQ(summary_rows[0][0], "18");
  EXPECT_EQ(summary_rows[1][0], "33");
  for (const auto& row : summary_rows) {
    ASSERT_EQ(row.size(), 8U) << text;
    const Counted& n = counted[std::stod(row[0])];
    EXPECT_GE(n.frames, 1) << row[0];
    EXPECT_EQ(std::stoi(row[1]), n.frames) << row[0];
    EXPECT_EQ(std::stoi(row[1]) + std::stoi(row[2]), 2) << row[0];  // reached or not, once per scene
    EXPECT_EQ(row[3], "0") << row[0];                                // spoiled
    EXPECT_EQ(std::stoi(row[4]), n.objects) << row[0];
    EXPECT_EQ(std::stoi(row[5]), n.found) << row[0];
  }
}

// One scene asked for with --scenes still ends with its summary; without --scenes there is none.
TEST(EvaluateDetector, ScenesOneStillSumsUp) {
  const fs::path log = logFile("one");
  ASSERT_EQ(runTool(kEvaluate + " --paper-brightness --seed 1181 --scenes 1 --levels 33 --size 640x400", log), 0)
      << readText(log);
  EXPECT_NE(readText(log).find("Scenes of seeds 1181-1181"), std::string::npos) << readText(log);
  ASSERT_EQ(runTool(kEvaluate + " --paper-brightness --seed 1181 --levels 33 --size 640x400", log), 0) << readText(log);
  EXPECT_EQ(readText(log).find("Scenes of seeds"), std::string::npos) << readText(log);
  fs::remove(log);
}

// Tables that cannot be written (a full disk) are no finished evaluation: exit 1, said on stderr.
TEST(EvaluateDetector, ResultsThatCannotBeWrittenAreNotAFinishedRun) {
  const fs::path log = logFile("full");
  const int status = std::system((kEvaluate + " --paper-brightness --seed 1181 --levels 33 --size 640x400 >/dev/full 2>" +
                                  log.string()).c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_NE(readText(log).find("the results could not be written to standard output"), std::string::npos)
      << readText(log);
  fs::remove(log);
}

// --luma exposes every sampled scene to a mean luma in the range given: two scenes at 14-16 both fall in the
// summary's darkest bin.
TEST(EvaluateDetector, LumaSetsTheExposureOfTheSampledPairs) {
  const fs::path log = logFile("luma");
  const int status = runTool(kEvaluate + " --random 2 --seed 1181 --size 320x200 --luma 14,16", log);
  const std::string text = readText(log);
  fs::remove(log);
  ASSERT_EQ(status, 0) << text;
  std::map<std::string, int> frames_per_bin;
  std::stringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const std::vector<std::string> c = cells(line);
    if (c.size() > 2 && c[0] == "luma") frames_per_bin[c[1]] = std::stoi(c[2]);
  }
  EXPECT_EQ(frames_per_bin["0-40"], 2) << text;
  for (const auto& [bin, frames] : frames_per_bin) {
    if (bin != "0-40") {
      EXPECT_EQ(frames, 0) << bin << "\n" << text;
    }
  }
}

// --focal-mm and --baseline-m give each sampled scene optics of its own (a head and a detector calibrated for it):
// the records say which, the summary bins pairs by focal length x baseline, and a head whose workspace spans more
// disparities than block matching searches is taken, its near end left out.
TEST(EvaluateDetector, OpticsAreDrawnPerPairWhenAsked) {
  const fs::path log = logFile("optics"), json = logFile("optics_json");
  const int status = runTool(kEvaluate + " --random 3 --seed 1181 --size 640x400 --focal-mm 4,24 --baseline-m 0.06,1.5"
                                         " --json " + json.string(), log);
  const std::string text = readText(log);
  fs::remove(log);
  ASSERT_EQ(status, 0) << text;
  EXPECT_NE(text.find("| focal x baseline px m |"), std::string::npos) << text;
  const std::string records = readText(json);
  fs::remove(json);
  EXPECT_NE(records.find(" --focal-mm 4,24 --baseline-m 0.06,1.5\""), std::string::npos) << records.substr(0, 200);
  std::set<double> focal, baseline;
  double widest = 0;  // [px m] focal length x baseline
  const std::regex optics("\"focal_px\": ([0-9.e+-]+), \"baseline_m\": ([0-9.e+-]+)");
  for (auto it = std::sregex_iterator(records.begin(), records.end(), optics); it != std::sregex_iterator(); ++it) {
    focal.insert(std::stod((*it)[1]));
    baseline.insert(std::stod((*it)[2]));
    widest = std::max(widest, std::stod((*it)[1]) * std::stod((*it)[2]));
    EXPECT_GE(std::stod((*it)[2]), 0.06);
    EXPECT_LE(std::stod((*it)[2]), 1.5);
  }
  EXPECT_GT(widest, 1024 / (1 / 0.5 - 1 / 5.0)) << "no pair's workspace spans more disparities than are searched";
  EXPECT_EQ(focal.size(), 3U);
  EXPECT_EQ(baseline.size(), 3U);
}

// A scene object of a colour the configuration does not designate counts as a distractor, and is named so: a
// misspelt colour is seen for what it is, not as a buoy the detector missed. A scene that cannot be rendered is named
// before anything is.
TEST(EvaluateDetector, SceneObjectsOfUndesignatedColoursAreNamed) {
  const fs::path scene = fs::temp_directory_path() / ("evaluate_detector_test_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(scene) << "name: typo\nrig: {width: 640, height: 400, pixel_size_um: 17.58}\nobjects:\n"
                          "  - {name: buoy, shape: sphere, colour: rde, albedo: [0.8, 0.1, 0.1], position_m: [0, 0, 2],"
                          " diameter_m: 0.3}\n"
                          "  - {name: ball, shape: sphere, colour: yellow, albedo: [0.85, 0.75, 0.08],"
                          " position_m: [0.4, 0, 2.5], diameter_m: 0.3}\n";
  const fs::path log = logFile("typo");
  ASSERT_EQ(runTool(kEvaluate + " --frames 1 " + scene.string(), log), 0) << readText(log);
  const std::string text = readText(log);
  EXPECT_NE(text.find(": counted as distractors, their colours not designated here: buoy (rde)\n"), std::string::npos)
      << text;
  EXPECT_EQ(text.find("ball (yellow)"), std::string::npos) << text;
  // A scene that cannot be rendered (the camera inside the buoy) is named as such before any scene is rendered.
  const fs::path inside = scene.string() + ".inside.yaml";
  std::ofstream(inside) << "name: inside\nrig: {width: 640, height: 400, pixel_size_um: 17.58}\nobjects:\n"
                           "  - {name: buoy, shape: sphere, colour: red, position_m: [0, 0, 0.1], diameter_m: 0.5}\n";
  EXPECT_EQ(runTool(kEvaluate + " --frames 1 " + scene.string() + " " + inside.string(), log), 2) << readText(log);
  const std::string refused = readText(log);
  EXPECT_NE(refused.find(inside.string() + ": invalid scene"), std::string::npos) << refused;
  EXPECT_NE(refused.find("objects[0] (buoy): the left camera lies inside it at time 0"), std::string::npos) << refused;
  EXPECT_EQ(refused.find("the detector refuses its rig"), std::string::npos) << refused;
  EXPECT_NE(text.find("| " + scene.filename().string() + " |"), std::string::npos) << text;  // its row when rendered
  EXPECT_EQ(refused.find("| " + scene.filename().string() + " |"), std::string::npos)
      << "a scene rendered before the refusal: " << refused;
  // One whose camera moves into the buoy at later frames: the same, those frames named, nothing rendered.
  std::ofstream(inside) << "name: walk_into\nrig: {width: 640, height: 400, pixel_size_um: 17.58}\n"
                           "camera_motion: {velocity_mps: [0.0, 0.0, 1.0]}\nobjects:\n"
                           "  - {name: buoy, shape: sphere, colour: red, position_m: [0, 0, 2], diameter_m: 0.3}\n";
  EXPECT_EQ(runTool(kEvaluate + " --frames 30 --rate 10 " + scene.string() + " " + inside.string(), log), 2)
      << readText(log);
  const std::string later = readText(log);
  EXPECT_NE(later.find(inside.string() + ": cannot be rendered"), std::string::npos) << later;
  EXPECT_NE(later.find("objects[0] (buoy): the left camera lies inside it at frames 19-21 (of 30 at 10 Hz)"),
            std::string::npos)
      << later;
  EXPECT_EQ(later.find("| " + scene.filename().string() + " |"), std::string::npos) << later;
  fs::remove(inside);
  fs::remove(scene);
  fs::remove(log);
}
