// SPDX-License-Identifier: BSD-3-Clause
// render_scene --random end to end: sampled scenes in, images, Pascal VOC XML and label masks out.
#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <unistd.h>

#include "tool_test_helpers.h"

namespace fs = std::filesystem;

namespace {

int run(const std::string& args) { return underwater_stereo::runTool(std::string(UWS_RENDER_SCENE) + " " + args); }

using underwater_stereo::readText;

}  // namespace

TEST(RenderScene, RandomScenesBecomeVocTrainingData) {
  const fs::path out = fs::temp_directory_path() / ("render_scene_test_" + std::to_string(::getpid()));
  ASSERT_EQ(run("--random 3 --seed 77 --size 320x200 --out " + out.string()), 0);
  for (int seed = 77; seed < 80; ++seed) {
    const std::string id = "0000" + std::to_string(seed);
    SCOPED_TRACE(id);
    const cv::Mat image = cv::imread((out / "images" / (id + ".png")).string(), cv::IMREAD_UNCHANGED);
    const cv::Mat mask = cv::imread((out / "masks" / (id + ".png")).string(), cv::IMREAD_UNCHANGED);
    const std::string xml = readText(out / "annotations" / (id + ".xml"));
    ASSERT_EQ(image.type(), CV_8UC3);
    ASSERT_EQ(mask.type(), CV_8UC1);
    EXPECT_EQ(image.size(), cv::Size(320, 200));
    EXPECT_EQ(mask.size(), image.size());
    ASSERT_EQ(xml.rfind("<annotation>", 0), 0U);
    EXPECT_NE(xml.find("<filename>" + id + ".png</filename>"), std::string::npos);
    EXPECT_NE(xml.find("</annotation>"), std::string::npos);
    // k-th <object> <-> mask value k: as many objects as mask labels, each box around its label's pixels.
    const std::regex box("<name>(red|orange|yellow|green)</name>[^]*?<xmin>([0-9]+)</xmin><ymin>([0-9]+)</ymin>"
                         "<xmax>([0-9]+)</xmax><ymax>([0-9]+)</ymax>");
    int k = 0;
    for (auto it = std::sregex_iterator(xml.begin(), xml.end(), box); it != std::sregex_iterator(); ++it) {
      ++k;
      const cv::Rect r = cv::boundingRect(mask == k);
      EXPECT_EQ(std::stoi((*it)[2]), r.x + 1);
      EXPECT_EQ(std::stoi((*it)[3]), r.y + 1);
      EXPECT_EQ(std::stoi((*it)[4]), r.x + r.width);
      EXPECT_EQ(std::stoi((*it)[5]), r.y + r.height);
    }
    double max_label = 0;
    cv::minMaxLoc(mask, nullptr, &max_label);
    EXPECT_EQ(static_cast<int>(max_label), k);
  }
  EXPECT_EQ(run("--random 2 --scene x.yaml --out " + out.string()), 2);  // modes do not mix
  EXPECT_EQ(run("--random 2"), 2);                                       // no --out
  EXPECT_EQ(run("--random 2 --seed 12abc --out " + out.string()), 2);    // a number with text after it
  EXPECT_EQ(run("--random 2.5 --out " + out.string()), 2);
  EXPECT_EQ(run("--random 2 --frames 3 --out " + out.string()), 2);     // --frames goes with --scene
  EXPECT_EQ(run("--random 2 --namespace s --out " + out.string()), 2);
  EXPECT_EQ(run("--random 2 --seed 1 --seed 2 --out " + out.string()), 2);  // which seed was meant?
  EXPECT_EQ(run("--scene /nonexistent.yaml --png-dir " + out.string()), 2);  // a scene that cannot be read
  fs::remove_all(out);
}

// A start time or namespace a bag cannot hold is refused before anything is rendered (exit 2, nothing written).
TEST(RenderScene, StampsAndTopicsABagCannotHoldAreRefused) {
  const fs::path bag = fs::temp_directory_path() / ("render_scene_refused_" + std::to_string(::getpid()) + ".bag");
  const std::string scene = " --scene " UWS_SOURCE_DIR "/test/scenes/small_pool.yaml --frames 1 --bag " + bag.string();
  for (const char* bad : {"--start-time nan", "--start-time -5", "--start-time 1e300", "--namespace 'bad name!'",
                          "--frames 2abc", "--rate 0", "--rate 15hz", "--start-time 4294967296",
                          "--namespace a//b", "--namespace '~private'",
                          // options of the other mode, which would be ignored
                          "--size 320x200", "--seed 3", "--luma 12,40", "--out /tmp/x"}) {
    EXPECT_EQ(run(std::string(bad) + scene), 2) << bad;
    EXPECT_FALSE(fs::exists(bag)) << bad;
  }
}

// A scene whose camera lies inside an object (it would see only the object's inside) is refused as a bad scene: exit
// 2, the object named, nothing written.
TEST(RenderScene, ASceneWithTheCameraInsideAnObjectIsRefused) {
  const fs::path dir = fs::temp_directory_path() / ("render_scene_inside_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir / "inside.yaml") << "rig: {width: 640, height: 400, pixel_size_um: 17.58}\nobjects:\n"
                                        "  - {name: crate, shape: box, colour: red, position_m: [0, 0, 0.1],"
                                        " size_m: [0.5, 0.5, 0.5]}\n";
  const fs::path log = dir / "render.log";
  const std::string args = "--scene " + (dir / "inside.yaml").string() + " --frames 1 --png-dir " + (dir / "png").string();
  EXPECT_EQ(underwater_stereo::runTool(std::string(UWS_RENDER_SCENE) + " " + args, log), 2);
  EXPECT_NE(readText(log).find("objects[0] (crate): the left camera lies inside it at time 0"), std::string::npos)
      << readText(log);
  EXPECT_FALSE(fs::exists(dir / "png" / "left_0000.png"));
  // A camera that moves into an object at later frames: the same, those frames named as one range (their ground truth
  // had been the whole image, their picture water).
  std::ofstream(dir / "walk_into.yaml") << "rig: {width: 640, height: 400, pixel_size_um: 17.58}\n"
                                           "camera_motion: {velocity_mps: [0.0, 0.0, 1.0]}\nobjects:\n"
                                           "  - {name: buoy, shape: sphere, colour: yellow, position_m: [0, 0, 2],"
                                           " diameter_m: 0.3}\n";
  const std::string walk = "--scene " + (dir / "walk_into.yaml").string() + " --frames 30 --rate 10 --png-dir " +
                           (dir / "png").string();
  EXPECT_EQ(underwater_stereo::runTool(std::string(UWS_RENDER_SCENE) + " " + walk, log), 2);
  EXPECT_NE(readText(log).find((dir / "walk_into.yaml").string() + ": cannot be rendered"), std::string::npos)
      << readText(log);
  EXPECT_NE(readText(log).find("objects[0] (buoy): the left camera lies inside it at frames 19-21 (of 30 at 10 Hz)"),
            std::string::npos)
      << readText(log);
  // A scene file that cannot be read is named once (the reader names it).
  EXPECT_EQ(underwater_stereo::runTool(std::string(UWS_RENDER_SCENE) + " --png-dir " + (dir / "png").string() + " --scene " +
                                         (dir / "absent.yaml").string(), log),
            2);
  const std::string unread = readText(log);
  EXPECT_NE(unread.find((dir / "absent.yaml").string()), std::string::npos) << unread;
  EXPECT_EQ(unread.find((dir / "absent.yaml").string()), unread.rfind((dir / "absent.yaml").string())) << unread;
  EXPECT_FALSE(fs::exists(dir / "png" / "left_0000.png"));
  fs::remove_all(dir);
}

// The sampler's options (--size WxH, --luma LO,HI, --focal-mm LO,HI, --baseline-m LO,HI): a value the sampler cannot take is named as given, one that is
// not of the option's form as such; exit 2, nothing written.
TEST(RenderScene, BadSamplerOptionsAreNamedAsGiven) {
  const fs::path out = fs::temp_directory_path() / ("render_scene_sampler_" + std::to_string(::getpid()));
  const fs::path log = out.string() + ".log";
  const struct {
    std::string option, named;
  } cases[] = {{"--size 10x10", "--size 10x10: width"}, {"--size 320x200px", "--size: '320x200px' is not WIDTHxHEIGHT"},
               {"--size 320", "--size: '320' is not WIDTHxHEIGHT"}, {"--luma 5,300", "--luma 5,300: target_luma"},
               {"--luma 40,12", "--luma 40,12: target_luma"}, {"--luma 12,40x", "--luma: '12,40x' is not LO,HI"},
               {"--luma 12", "--luma: '12' is not LO,HI"},
               {"--focal-mm 0.5,8", "--focal-mm 0.5,8: focal_length_mm"}, {"--baseline-m 0.2,0.1", "--baseline-m 0.2,0.1: baseline_m"},
               {"--focal-mm 8", "--focal-mm: '8' is not LO,HI"},
               {"--size 640x401", "--size 640x401: width and height must be even"},
               {"--scene config/scenes/ball.yaml", "--scene and --random N are two modes: give one of them"},
               // Beyond an int: refused, not wrapped around to 640x400.
               {"--size 4294967936x4294967696", "--size: '4294967936x4294967696' is not WIDTHxHEIGHT"}};
  for (const auto& c : cases) {
    EXPECT_EQ(underwater_stereo::runTool(std::string(UWS_RENDER_SCENE) + " --random 1 " + c.option + " --out " +
                                             out.string(),
                                         log),
              2)
        << c.option;
    EXPECT_NE(readText(log).find(c.named), std::string::npos) << readText(log);
    EXPECT_FALSE(fs::exists(out)) << c.option;
  }
  fs::remove(log);
}

// --focal-mm draws the lens of each sampled scene: the same seed through a long lens shows its objects larger.
TEST(RenderScene, FocalLengthSetsTheSampledScenesLens) {
  const fs::path out = fs::temp_directory_path() / ("render_scene_focal_" + std::to_string(::getpid()));
  const fs::path log = out.string() + ".log";
  std::map<std::string, int> labelled_pixels;
  for (const std::string lens : {"4,4", "12,12"}) {
    ASSERT_EQ(underwater_stereo::runTool(std::string(UWS_RENDER_SCENE) + " --random 1 --seed 1181 --size 320x200 --focal-mm " +
                                             lens + " --out " + (out / lens).string(),
                                         log),
              0)
        << readText(log);
    const cv::Mat mask = cv::imread((out / lens / "masks" / "001181.png").string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(mask.empty()) << lens;
    labelled_pixels[lens] = cv::countNonZero(mask);
  }
  EXPECT_GT(labelled_pixels["12,12"], 2 * labelled_pixels["4,4"]);
  EXPECT_GT(labelled_pixels["4,4"], 0);
  fs::remove_all(out);
  fs::remove(log);
}

// --luma sets the mean luma the sampled scenes are exposed to (dark water to learn from).
TEST(RenderScene, LumaSetsTheExposureOfTheSampledScenes) {
  const fs::path out = fs::temp_directory_path() / ("render_scene_luma_" + std::to_string(::getpid()));
  auto mean_luma = [&](const std::string& luma) {
    fs::remove_all(out);
    EXPECT_EQ(run("--random 1 --seed 77 --size 320x200 --luma " + luma + " --out " + out.string()), 0) << luma;
    cv::Mat grey;
    cv::cvtColor(cv::imread((out / "images" / "000077.png").string()), grey, cv::COLOR_BGR2GRAY);
    return cv::mean(grey)[0];
  };
  EXPECT_NEAR(mean_luma("14,16"), 15, 5);
  EXPECT_NEAR(mean_luma("180,182"), 181, 8);
  fs::remove_all(out);
}

// A second render into the same --png-dir holds its own frames only: none of a longer earlier render is left
// behind to be read as this scene's (other files in the directory stay).
TEST(RenderScene, PngDirHoldsThisRendersFramesOnly) {
  const fs::path out = fs::temp_directory_path() / ("render_scene_png_" + std::to_string(::getpid()));
  const std::string scene = " --scene " UWS_SOURCE_DIR "/test/scenes/small_pool.yaml --png-dir " + out.string();
  ASSERT_EQ(run("--frames 3" + scene), 0);
  EXPECT_TRUE(fs::exists(out / "left_0002.png"));
  std::ofstream(out / "notes.txt") << "mine\n";
  ASSERT_EQ(run("--frames 1" + scene), 0);
  EXPECT_TRUE(fs::exists(out / "left_0000.png"));
  EXPECT_TRUE(fs::exists(out / "right_0000.png"));
  for (const char* stale : {"left_0001.png", "right_0001.png", "left_0002.png", "right_0002.png"}) {
    EXPECT_FALSE(fs::exists(out / stale)) << stale;
  }
  EXPECT_EQ(readText(out / "notes.txt"), "mine\n");
  fs::remove_all(out);
}
