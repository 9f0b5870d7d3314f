// SPDX-License-Identifier: BSD-3-Clause
// detect_files end to end: rendered PNGs and camera_info YAML in, one JSON line per detection out.
#include <camera_calibration_parsers/parse.h>
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>

#include "tool_test_helpers.h"
#include "underwater_stereo/ros_glue/calibration_conversions.h"
#include "underwater_stereo/sim/renderer.h"

using namespace underwater_stereo;

namespace {

struct ToolRun {
  int status = -1;
  std::vector<std::string> lines;
};

/// detect_files with `args`: its exit status and its output's lines (stdout, and stderr too with `with_stderr`).
ToolRun run(const std::string& args, bool with_stderr = false) {
  ToolRun r;
  FILE* pipe =
      ::popen((std::string(UWS_DETECT_FILES) + " " + args + (with_stderr ? " 2>&1" : " 2>/dev/null")).c_str(), "r");
  char buf[8192];
  while (pipe && std::fgets(buf, sizeof buf, pipe)) r.lines.emplace_back(buf);
  r.status = pipe ? WEXITSTATUS(::pclose(pipe)) : -1;
  return r;
}

double field(const std::string& line, const std::string& name) {
  std::smatch m;
  if (!std::regex_search(line, m, std::regex("\"" + name + "\": ([-0-9.e]+)"))) return NAN;
  return std::stod(m[1]);
}

class DetectFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("detect_files_test_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    sim::Scene scene = sim::loadSceneFile(UWS_SOURCE_DIR "/test/scenes/small_pool.yaml");
    scene.sensor.encoding = "bgr8";
    const sim::Renderer renderer(scene);
    pair_ = renderer.render(0.0, 0);
    cv::imwrite(path("left.png"), pair_.left);
    cv::imwrite(path("right.png"), pair_.right);
    camera_calibration_parsers::writeCalibration(path("left.yaml"), "left",
                                                 ros_glue::toCameraInfo(renderer.calibration().left));
    camera_calibration_parsers::writeCalibration(path("right.yaml"), "right",
                                                 ros_glue::toCameraInfo(renderer.calibration().right));
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string stereoArgs() const {
    return "--left " + path("left.png") + " --right " + path("right.png") + " --left-info " + path("left.yaml") +
           " --right-info " + path("right.yaml") + " --config " UWS_SOURCE_DIR "/config/detector.yaml";
  }

  std::filesystem::path dir_;
  sim::RenderedPair pair_;
};

}  // namespace

TEST_F(DetectFiles, StereoPairGivesOneJsonLinePerObjectWithRangeAndPosition) {
  const ToolRun r = run(stereoArgs());
  ASSERT_EQ(r.status, 0);
  ASSERT_EQ(r.lines.size(), pair_.ground_truth.size());
  for (const auto& gt : pair_.ground_truth) {
    const auto line = std::find_if(r.lines.begin(), r.lines.end(), [&](const std::string& l) {
      return l.find("\"colour\": \"" + gt.colour + "\"") != std::string::npos;
    });
    ASSERT_NE(line, r.lines.end()) << gt.colour;
    EXPECT_NEAR(field(*line, "range"), gt.range_m, 0.03 * gt.range_m) << *line;
    EXPECT_NE(line->find("\"shape\": \"sphere\""), std::string::npos) << *line;
    EXPECT_NE(line->find("\"position\": ["), std::string::npos) << *line;
    EXPECT_NE(line->find("\"quality\": {\"status\": \"OK\""), std::string::npos) << *line;
  }
}

TEST_F(DetectFiles, ImageModeAndListFileGiveTwoDimensionalDetections) {
  std::ofstream(path("list.txt")) << "# one image, then the pair\n" << path("left.png") << "\n"
                                  << path("left.png") << " " << path("right.png") << "\n";
  const ToolRun r = run("--list " + path("list.txt") + " --left-info " + path("left.yaml") + " --right-info " +
                    path("right.yaml") + " --config " UWS_SOURCE_DIR "/config/detector.yaml");
  ASSERT_EQ(r.status, 0);
  ASSERT_EQ(r.lines.size(), 2 * pair_.ground_truth.size());
  int flat = 0;
  for (const auto& l : r.lines) flat += l.find("\"range\"") == std::string::npos;
  EXPECT_EQ(flat, static_cast<int>(pair_.ground_truth.size()));
  // A path with spaces, in double quotes; a folder given as the list is refused.
  std::filesystem::copy_file(path("left.png"), path("left copy.png"));
  std::ofstream(path("spaced.txt")) << "\"" << path("left copy.png") << "\"\n";
  EXPECT_EQ(run("--list " + path("spaced.txt")).lines.size(), pair_.ground_truth.size());
  const ToolRun folder = run("--list " + dir_.string(), true);
  EXPECT_EQ(folder.status, 2);
  ASSERT_FALSE(folder.lines.empty());
  EXPECT_NE(folder.lines[0].find(dir_.string() + ": a folder, not a file"), std::string::npos) << folder.lines[0];
  std::filesystem::remove(path("left copy.png"));
  const ToolRun image = run("--image '" + path("left*.png") + "'");  // a quoted glob
  ASSERT_EQ(image.status, 0);
  EXPECT_EQ(image.lines.size(), pair_.ground_truth.size());
  EXPECT_NE(image.lines[0].find("\"roi\": ["), std::string::npos);
}

// A head whose workspace (0.5-5 m) spans more disparities than block matching searches (a 1 m baseline: 1092) is
// taken, not refused: a note on stderr names the depths not ranged, and objects beyond them are found and ranged.
TEST_F(DetectFiles, ALongBaselineHeadIsTakenWithANoteOnTheDepthsNotRanged) {
  sim::Scene scene = sim::loadSceneFile(UWS_SOURCE_DIR "/test/scenes/small_pool.yaml");
  scene.sensor.encoding = "bgr8";
  scene.rig.baseline_m = 1.0;
  scene.objects[0].position_m = {0.4, 0.35, 2.5};  // both buoys in both views
  const sim::Renderer renderer(scene);
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  cv::imwrite(path("long_left.png"), pair.left);
  cv::imwrite(path("long_right.png"), pair.right);
  camera_calibration_parsers::writeCalibration(path("long_left.yaml"), "left", ros_glue::toCameraInfo(renderer.calibration().left));
  camera_calibration_parsers::writeCalibration(path("long_right.yaml"), "right",
                                               ros_glue::toCameraInfo(renderer.calibration().right));
  const ToolRun r = run("--left " + path("long_left.png") + " --right " + path("long_right.png") + " --left-info " +
                            path("long_left.yaml") + " --right-info " + path("long_right.yaml") +
                            " --config " UWS_SOURCE_DIR "/config/detector.yaml",
                        true);
  ASSERT_EQ(r.status, 0);
  ASSERT_EQ(r.lines.size(), 1 + pair.ground_truth.size());
  EXPECT_TRUE(std::regex_search(r.lines[0], std::regex("^detect_files: note: objects nearer than 0\\.5[0-9]+ m are not "
                                                       "ranged \\(stereo.min_depth_m 0\\.5\\): with focal length x baseline")))
      << r.lines[0];
  for (const auto& gt : pair.ground_truth) {
    const auto line = std::find_if(r.lines.begin(), r.lines.end(), [&](const std::string& l) {
      return l.find("\"colour\": \"" + gt.colour + "\"") != std::string::npos;
    });
    ASSERT_NE(line, r.lines.end()) << gt.colour;
    EXPECT_NEAR(field(*line, "range"), gt.range_m, 0.03 * gt.range_m) << *line;
  }
  // The head's own baseline: no note.
  EXPECT_EQ(run(stereoArgs(), true).lines.size(), pair_.ground_truth.size());
}

TEST_F(DetectFiles, BadInputIsAClearErrorNotACrash) {
  EXPECT_EQ(run("").status, 2);
  EXPECT_EQ(run("--image").status, 2);
  EXPECT_EQ(run("--left " + path("left.png")).status, 2) << "no right image";
  EXPECT_EQ(run(stereoArgs() + " --config /nonexistent.yaml").status, 2);
  std::ofstream(path("bad.yaml")) << "colours: [{name: red, hue: [170]}]\n";
  EXPECT_EQ(run(stereoArgs() + " --config " + path("bad.yaml")).status, 2);
  std::ofstream(path("garbage.yaml")) << "not: a camera\n";
  EXPECT_EQ(run("--left " + path("left.png") + " --right " + path("right.png") + " --left-info " +
                path("garbage.yaml") + " --right-info " + path("right.yaml")).status,
            2);
  // An unreadable frame and a size mismatch are skipped (exit 1); the good frame is still processed.
  cv::imwrite(path("small.png"), cv::Mat(100, 100, CV_8UC3, cv::Scalar(0, 0, 0)));
  std::ofstream(path("pairs.txt")) << path("missing.png") << " " << path("right.png") << "\n"
                                   << path("small.png") << " " << path("right.png") << "\n"
                                   << path("left.png") << " " << path("right.png") << "\n";
  const ToolRun r = run("--list " + path("pairs.txt") + " --left-info " + path("left.yaml") + " --right-info " +
                    path("right.yaml"));
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.lines.size(), pair_.ground_truth.size());
  // A stray word, a pattern that matches nothing and an unclosed quote in a list are each named (exit 2).
  auto firstLine = [&](const std::string& args) {
    const ToolRun r = run(args, true);
    return std::to_string(r.status) + " " + (r.lines.empty() ? std::string() : r.lines[0]);
  };
  EXPECT_NE(firstLine("--image " + path("left.png") + " stray.png").find("2 detect_files: stray argument 'stray.png'"),
            std::string::npos) << firstLine("--image " + path("left.png") + " stray.png");
  EXPECT_NE(firstLine("--left '" + path("left*.png") + "' --right '" + path("nothing_*.png") + "'")
                .find("--right '" + path("nothing_*.png") + "': no file matches the pattern"),
            std::string::npos);
  std::ofstream(path("quote.txt")) << "\"" << path("left.png") << "\n";
  EXPECT_NE(firstLine("--list " + path("quote.txt")).find(path("quote.txt") + ":1: a double quote not closed"),
            std::string::npos) << firstLine("--list " + path("quote.txt"));
  std::ofstream(path("glued.txt")) << "\"" << path("left.png") << "\"\"" << path("right.png") << "\"\n";
  EXPECT_NE(firstLine("--list " + path("glued.txt")).find(path("glued.txt") + ":1: text right after a closing double quote"),
            std::string::npos) << firstLine("--list " + path("glued.txt"));
  std::ofstream(path("inner_quote.txt")) << path("left") << "\"copy b.png\"\n";
  EXPECT_NE(firstLine("--list " + path("inner_quote.txt")).find(path("inner_quote.txt") + ":1: a double quote inside a word"),
            std::string::npos) << firstLine("--list " + path("inner_quote.txt"));
  std::ofstream(path("trailing_comment.txt")) << path("left.png") << " " << path("right.png") << " # the first pair\n";
  EXPECT_NE(firstLine("--list " + path("trailing_comment.txt"))
                .find(path("trailing_comment.txt") + ":1: a comment after a path"),
            std::string::npos) << firstLine("--list " + path("trailing_comment.txt"));
  // An empty quoted path (a stereo line would have become a 2D frame) and a NUL byte are named too.
  std::ofstream(path("empty_path.txt")) << path("left.png") << " \"\"\n";
  EXPECT_NE(firstLine("--list " + path("empty_path.txt")).find(path("empty_path.txt") + ":1: an empty path"),
            std::string::npos) << firstLine("--list " + path("empty_path.txt"));
  std::ofstream(path("nul.txt")) << path("left.png") << std::string(1, '\0') << "junk\n";
  EXPECT_NE(firstLine("--list " + path("nul.txt")).find(path("nul.txt") + ":1: a NUL byte"), std::string::npos)
      << firstLine("--list " + path("nul.txt"));
  // An option of one value given twice: refused, not the last one taken (the first list's frames were dropped).
  EXPECT_NE(firstLine("--list " + path("pairs.txt") + " --list " + path("pairs.txt")).find("--list is given twice"),
            std::string::npos);
  std::ofstream(path("empty_list.txt")) << "# nothing\n  # an indented comment\n\t\n";
  EXPECT_NE(firstLine("--list " + path("empty_list.txt")).find("the list file " + path("empty_list.txt") + " names no frame"),
            std::string::npos) << firstLine("--list " + path("empty_list.txt"));
  std::ofstream(path("bom.txt")) << "\xEF\xBB\xBF" << path("left.png") << "\r\n";  // as a Windows editor saves it
  EXPECT_EQ(run("--list " + path("bom.txt")).status, 0);
  // A grey image is searched, and said to hold no colour.
  cv::Mat grey;
  cv::cvtColor(pair_.left, grey, cv::COLOR_BGR2GRAY);
  cv::imwrite(path("grey.png"), grey);
  const ToolRun g = run("--image " + path("grey.png"), true);
  EXPECT_EQ(g.status, 0);
  ASSERT_EQ(g.lines.size(), 2u);
  EXPECT_EQ(g.lines[0], "detect_files: " + path("grey.png") +
                            ": a grey image (its three channels equal): no colour can be named in it\n");
  EXPECT_NE(g.lines[1].find("\"id\": null"), std::string::npos) << g.lines[1];
}

TEST_F(DetectFiles, NeitherAMadeUpRangeNorALostResultGoesUnsaid) {
  // One image as both views is skipped, named (its objects' ranges would be made up); the true pair is still measured.
  std::ofstream(path("pairs.txt")) << path("left.png") << " " << path("left.png") << "\n"
                                   << path("left.png") << " " << path("right.png") << "\n";
  const ToolRun twice = run("--list " + path("pairs.txt") + " --left-info " + path("left.yaml") + " --right-info " +
                            path("right.yaml"), true);
  EXPECT_EQ(twice.status, 1);
  int ranged = 0, named = 0;
  for (const std::string& l : twice.lines) {
    ranged += l.find("\"range\"") != std::string::npos;
    named += l.find("the left and right frames are the same image") != std::string::npos;
  }
  EXPECT_EQ(ranged, static_cast<int>(pair_.ground_truth.size()));
  EXPECT_EQ(named, 1);
  // A name that is a file as it is stays that file, though it reads as a pattern (img[1].png is not img1.png).
  std::filesystem::copy_file(path("left.png"), path("img[1].png"));
  cv::imwrite(path("img1.png"), cv::Mat(pair_.left.size(), CV_8UC3, cv::Scalar(90, 80, 20)));
  const ToolRun literal = run("--image '" + path("img[1].png") + "'");
  ASSERT_EQ(literal.status, 0);
  ASSERT_EQ(literal.lines.size(), pair_.ground_truth.size());
  EXPECT_NE(literal.lines[0].find("img[1].png"), std::string::npos) << literal.lines[0];
  // Results that cannot be written (a full disk) stop the run with exit 1 and say so, not exit 0.
  const std::string log = path("full.log");
  const int status = std::system((std::string(UWS_DETECT_FILES) + " --image " + path("left.png") + " --image " +
                                  path("left.png") + " > /dev/full 2> " + log).c_str());
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_NE(readText(log).find("the results cannot be written to standard output"), std::string::npos) << readText(log);
}

TEST_F(DetectFiles, ExplainListsWhatWasLookedAtAndNotReportedWithWhy) {
  // A learnt model asked for unanimous trees: regions some colour got votes for are reported as rejected.
  std::ofstream(path("strict.yaml")) << "colours: [{name: red}, {name: orange}, {name: yellow}, {name: green}]\n"
                                        "candidates: {source: learned}\n"
                                        "colour_model: {file: " UWS_SOURCE_DIR "/config/detector.colour_model.yml.gz, "
                                        "min_confidence: 1.0}\n";
  const std::string args = "--image " + path("left.png") + " --config " + path("strict.yaml");
  const ToolRun explained = run(args + " --explain");
  ASSERT_EQ(explained.status, 0);
  int rejected = 0;
  for (const auto& l : explained.lines) {
    if (l.find("\"rejected\"") == std::string::npos) continue;
    ++rejected;
    EXPECT_NE(l.find("\"stage\": \"colour uncertain\", \"reason\": \"colour confidence"), std::string::npos) << l;
  }
  EXPECT_GT(rejected, 0);
  for (const auto& l : run(args).lines) EXPECT_EQ(l.find("\"rejected\""), std::string::npos) << "only with --explain";
}
