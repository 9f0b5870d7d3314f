// SPDX-License-Identifier: BSD-3-Clause
// The learning tools end to end: learn_colours on frames and VOC labels that render_scene wrote, learnt over the
// default configuration, gives a configuration that loads wherever it was written; learn_checks learns from records
// and refuses records it cannot learn from; a grey frame is refused; learn_checks and learn_shapes name a records
// folder, a records file given twice (or a copy of one), an output they cannot write and a malformed record before
// learning anything.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include "tool_test_helpers.h"
#include "underwater_stereo/detection/detection_check.h"
#include "underwater_stereo/detection/detector_config.h"
#include "underwater_stereo/detection/shape_features.h"

namespace fs = std::filesystem;
using namespace underwater_stereo;


TEST(LearnColours, AConfigLearntOverTheDefaultLoadsFromAnotherFolder) {
  const fs::path dir = fs::temp_directory_path() / ("learn_colours_test_" + std::to_string(::getpid()));
  fs::create_directories(dir / "pool");
  ASSERT_EQ(runTool(std::string(UWS_RENDER_SCENE) + " --random 10 --seed 50000 --size 640x400 --out " + (dir / "sim").string(),
                dir / "render.log"),
            0)
      << readText(dir / "render.log");
  // Orange and yellow are taught as background: two colours are enough here, and ten scenes hold both.
  const std::string learn = std::string(UWS_LEARN_COLOURS) + " --images " + (dir / "sim/images").string() +
                            " --annotations " + (dir / "sim/annotations").string() + " --base " UWS_SOURCE_DIR
                            "/config/detector.yaml --colours red,green --background orange,yellow --folds 1 --out " +
                            (dir / "pool/pool.yaml").string();
  ASSERT_EQ(runTool(learn, dir / "learn.log"), 0) << readText(dir / "learn.log");
  // The base's check after stereo read the base's colour model's votes: said, and not written.
  EXPECT_NE(readText(dir / "learn.log").find("check_file is neither used nor written"), std::string::npos);
  const std::string written = readText(dir / "pool/pool.yaml");
  EXPECT_EQ(written.find("check_file"), std::string::npos) << written;
  // The base's shape model, named relative to the base's folder, is still found from the new one.
  const DetectorConfig c = loadDetectorConfigFile((dir / "pool/pool.yaml").string());
  EXPECT_TRUE(c.shape.model);
  ASSERT_TRUE(c.learned.model);
  EXPECT_EQ(c.learned.model->colours(), (std::vector<std::string>{"red", "green"}));
  EXPECT_FALSE(c.learned.check);
  // Tables that cannot be printed (a full disk) are said and the run ends with 1, the learnt files still written.
  fs::remove(dir / "pool/pool.yaml");
  fs::remove(dir / "pool/pool.colour_model.yml.gz");
  const int full = std::system((learn + " >/dev/full 2>" + (dir / "full.log").string()).c_str());
  EXPECT_EQ(WEXITSTATUS(full), 1);
  EXPECT_NE(readText(dir / "full.log").find("what it printed could not be written to standard output"),
            std::string::npos) << readText(dir / "full.log");
  EXPECT_TRUE(fs::exists(dir / "pool/pool.yaml"));
  EXPECT_TRUE(fs::exists(dir / "pool/pool.colour_model.yml.gz"));

  // A base whose colour model and check are missing serves as well: both are replaced, never read; and a colour the
  // base does not list (green, dropped from it) is learnt and written by its name.
  YAML::Node moved = YAML::LoadFile(UWS_SOURCE_DIR "/config/detector.yaml");
  YAML::Node without_green(YAML::NodeType::Sequence);
  for (const YAML::Node& colour : moved["colours"]) {
    if (colour["name"].as<std::string>() != "green") without_green.push_back(colour);
  }
  moved["colours"] = without_green;
  moved["colour_model"]["file"] = (dir / "missing.colour_model.yml.gz").string();
  moved["colour_model"]["check_file"] = (dir / "missing.check_model.yml.gz").string();
  moved["shape"]["model_file"] = UWS_SOURCE_DIR "/config/" + moved["shape"]["model_file"].as<std::string>();
  std::ofstream(dir / "moved.yaml") << moved;
  std::string from_moved = learn;
  from_moved.replace(from_moved.find(UWS_SOURCE_DIR "/config/detector.yaml"),
                     std::string(UWS_SOURCE_DIR "/config/detector.yaml").size(), (dir / "moved.yaml").string());
  ASSERT_EQ(runTool(from_moved, dir / "learn_moved.log"), 0) << readText(dir / "learn_moved.log");
  const DetectorConfig from_it = loadDetectorConfigFile((dir / "pool/pool.yaml").string());
  EXPECT_TRUE(from_it.learned.model);
  ASSERT_EQ(from_it.colours.classes.size(), 2U);
  EXPECT_EQ(from_it.colours.classes[1].name, "green");
  fs::remove_all(dir);
}

TEST(LearnColours, AGreyFrameIsRefusedNamingIt) {
  const fs::path dir = fs::temp_directory_path() / ("learn_colours_grey_" + std::to_string(::getpid()));
  fs::create_directories(dir / "images");
  fs::create_directories(dir / "annotations");
  cv::Mat grey(120, 160, CV_8UC1, cv::Scalar(90));
  cv::circle(grey, {80, 60}, 20, cv::Scalar(160), -1);
  cv::imwrite((dir / "images/frame.png").string(), grey);
  std::ofstream(dir / "annotations/frame.xml")
      << "<annotation><object><name>buoy_red</name><bndbox><xmin>60</xmin><ymin>40</ymin><xmax>100</xmax>"
         "<ymax>80</ymax></bndbox></object></annotation>";
  const std::string learn = std::string(UWS_LEARN_COLOURS) + " --images " + (dir / "images").string() +
                            " --annotations " + (dir / "annotations").string() + " --out " + (dir / "out.yaml").string();
  EXPECT_EQ(runTool(learn, dir / "learn.log"), 1);
  EXPECT_NE(readText(dir / "learn.log").find("frame.png: a grey image (its three channels equal) cannot teach colours"),
            std::string::npos)
      << readText(dir / "learn.log");
  EXPECT_FALSE(fs::exists(dir / "out.yaml"));
  fs::remove_all(dir);
}

// learn_colours refuses, before learning, what would be learnt wrongly or not at all: two images of one frame, an
// annotation without its image, and in the same run a bad label of a frame that was read; one frame twice (a copy in
// another folder), held-out detections asked for without folds, a fractional fold count.
TEST(LearnColours, FramesAndOptionsItCannotLearnFromAreNamed) {
  const fs::path dir = fs::temp_directory_path() / ("learn_colours_frames_" + std::to_string(::getpid()));
  fs::create_directories(dir / "images");
  fs::create_directories(dir / "annotations");
  cv::Mat frame(120, 160, CV_8UC3, cv::Scalar(120, 90, 30));
  cv::circle(frame, {80, 60}, 20, cv::Scalar(30, 40, 200), -1);
  cv::imwrite((dir / "images/frame.png").string(), frame);
  cv::imwrite((dir / "images/frame.jpg").string(), frame);
  const std::string label = "<annotation><object><name>buoy_red</name><bndbox><xmin>60</xmin><ymin>40</ymin>"
                            "<xmax>100</xmax><ymax>80</ymax></bndbox></object></annotation>";
  std::ofstream(dir / "annotations/frame.xml") << label;
  std::ofstream(dir / "annotations/lost.xml") << label;
  // A frame read whole whose label is bad twice over: named in the same run as the frames that cannot be read.
  cv::Mat other = frame.clone();
  cv::circle(other, {30, 30}, 10, cv::Scalar(30, 200, 200), -1);
  cv::imwrite((dir / "images/other.png").string(), other);
  std::ofstream(dir / "annotations/other.xml") << "<annotation><object><name>buoy_purple</name><bndbox><xmin>60</xmin>"
                                                  "<ymin>40</ymin><xmax>900</xmax><ymax>80</ymax></bndbox></object>"
                                                  "</annotation>";
  const std::string learn = std::string(UWS_LEARN_COLOURS) + " --images " + (dir / "images").string() +
                            " --annotations " + (dir / "annotations").string() + " --out " + (dir / "out.yaml").string();
  EXPECT_EQ(runTool(learn, dir / "learn.log"), 1);
  const std::string log = readText(dir / "learn.log");
  EXPECT_NE(log.find("frame.png and frame.jpg share the annotation frame.xml"), std::string::npos) << log;
  EXPECT_NE(log.find("annotations/lost.xml: no image of that name"), std::string::npos) << log;
  EXPECT_NE(log.find("other.png: box 0 (buoy_purple)"), std::string::npos) << log;
  EXPECT_NE(log.find("names no designated colour"), std::string::npos) << log;
  EXPECT_NE(log.find("outside the 160x120 image"), std::string::npos) << log;
  // The same frame again, under another name in a second folder: it would be learnt twice.
  fs::create_directories(dir / "more_images");
  fs::create_directories(dir / "more_annotations");
  fs::copy_file(dir / "images/frame.jpg", dir / "more_images/copy.jpg");
  std::ofstream(dir / "more_annotations/copy.xml") << label;
  const std::string twice = learn + " --images " + (dir / "more_images").string() + " --annotations " +
                            (dir / "more_annotations").string();
  EXPECT_EQ(runTool(twice, dir / "learn.log"), 1);
  EXPECT_NE(readText(dir / "learn.log").find("more_images/copy.jpg is the same frame as " + (dir / "images/frame.jpg").string()),
            std::string::npos)
      << readText(dir / "learn.log");
  EXPECT_EQ(runTool(learn + " --folds 1 --detections-out " + (dir / "d.json").string(), dir / "learn.log"), 2);
  EXPECT_NE(readText(dir / "learn.log").find("--detections-out needs cross-validation"), std::string::npos);
  // An output over a file learnt from (a label here), or two outputs in one file: refused before anything is read.
  const std::string over_label = std::string(UWS_LEARN_COLOURS) + " --images " + (dir / "images").string() +
                                 " --annotations " + (dir / "annotations").string() + " --out " +
                                 (dir / "annotations/frame.xml").string();
  EXPECT_EQ(runTool(over_label, dir / "learn.log"), 2);
  EXPECT_NE(readText(dir / "learn.log").find("frame.xml is a file learnt from"), std::string::npos)
      << readText(dir / "learn.log");
  EXPECT_EQ(runTool(learn + " --detections-out " + (dir / "out.yaml").string(), dir / "learn.log"), 2);
  EXPECT_NE(readText(dir / "learn.log").find("out.yaml is also --out"), std::string::npos) << readText(dir / "learn.log");
  // The colour model is written beside --out: a folder in its place is named before anything is learnt.
  fs::create_directories(dir / "out.colour_model.yml.gz");
  EXPECT_EQ(runTool(learn, dir / "learn.log"), 2);
  EXPECT_NE(readText(dir / "learn.log").find("--out's colour model " + (dir / "out.colour_model.yml.gz").string() +
                                             " is a folder"),
            std::string::npos)
      << readText(dir / "learn.log");
  fs::remove(dir / "out.colour_model.yml.gz");
  EXPECT_EQ(runTool(learn + " --folds 2.5", dir / "learn.log"), 2);
  EXPECT_NE(readText(dir / "learn.log").find("--folds: '2.5' is not a whole number in [1, 100]"), std::string::npos)
      << readText(dir / "learn.log");
  EXPECT_FALSE(fs::exists(dir / "out.yaml"));
  fs::remove_all(dir);
}

namespace {

/// evaluate_detector --random records of one pair: a found red object, a detection on a distractor, one on an
/// object too far to count, each with `width` check features; made `--without-check` or not.
std::string records(std::size_t width, bool without_check) {
  std::string f = "[";
  for (std::size_t i = 0; i < width; ++i) f += (i ? ", " : "") + std::to_string(0.01 * i);
  f += "]";
  std::string objects;
  for (const char* colour : {"red", "orange", "yellow", "green"}) {
    objects += std::string(objects.empty() ? "" : ", ") + "{\"name\": \"" + colour + "_0\", \"colour\": \"" + colour +
               "\", \"designated\": true, \"eligible\": true, \"found\": true, \"detected\": {\"check_features\": " +
               f + "}}";
  }
  objects += ", {\"name\": \"grey_1\", \"colour\": \"grey\", \"designated\": false, \"eligible\": false, \"found\": false}";
  objects += ", {\"name\": \"red_far\", \"colour\": \"red\", \"designated\": true, \"eligible\": false, \"found\": false}";
  return std::string("{\"config\": \"config/detector.yaml") + (without_check ? " --without-check" : "") +
         "\", \"pairs\": [{\"seed\": 1, \"objects\": [" + objects + "], \"false_detections\": [" +
         "{\"on\": \"grey_1\", \"check_features\": " + f + "}, {\"on\": \"\", \"check_features\": " + f + "}, " +
         "{\"on\": \"red_far\", \"check_features\": " + f + "}]}]}";
}

}  // namespace

TEST(LearnChecks, LearnsFromRecordsMadeWithoutACheckAndRefusesOthers) {
  const fs::path dir = fs::temp_directory_path() / ("learn_checks_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const DetectorConfig base = loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml");
  const std::size_t width = checkFeatureNames(base.learned.model->colours()).size();
  auto learn = [&](const std::string& text, const std::string& name) {
    std::ofstream(dir / name) << text;
    return runTool(std::string(UWS_LEARN_CHECKS) + " --config " UWS_SOURCE_DIR "/config/detector.yaml --out " +
                   (dir / "check.yml.gz").string() + " " + (dir / name).string(),
               dir / "learn.log");
  };
  ASSERT_EQ(learn(records(width, true), "good.json"), 0) << readText(dir / "learn.log");
  // The four colours once each, the distractor and the background as background; the far red object not at all.
  EXPECT_NE(readText(dir / "learn.log").find("learnt from 6 detections (background 2, red 1"), std::string::npos)
      << readText(dir / "learn.log");
  const DetectorConfig checked = parseDetectorConfig(
      YAML::Load("colours: [{name: red}, {name: orange}, {name: yellow}, {name: green}]\ncandidates: {source: learned}\n"
                 "colour_model: {file: " UWS_SOURCE_DIR "/config/detector.colour_model.yml.gz, check_file: " +
                 (dir / "check.yml.gz").string() + "}"));
  EXPECT_TRUE(checked.learned.check);

  // --colours-from keeps that check's forest for naming colours (the committed check's, here; a forest alone serves too):
  // only the boosted trees are learnt.
  const std::string committed = UWS_SOURCE_DIR "/config/detector.check_model.yml.gz";
  ASSERT_EQ(runTool(std::string(UWS_LEARN_CHECKS) + " --config " UWS_SOURCE_DIR "/config/detector.yaml --out " +
                        (dir / "kept.yml.gz").string() + " --colours-from " + committed + " " + (dir / "good.json").string(),
                    dir / "learn.log"),
            0)
      << readText(dir / "learn.log");
  const std::vector<std::string>& colours = base.learned.model->colours();
  const DetectionCheck kept = DetectionCheck::load((dir / "kept.yml.gz").string(), colours);
  const DetectionCheck source = DetectionCheck::load(committed, colours);
  cv::Mat probe(8, static_cast<int>(width), CV_32F);
  cv::randu(probe, -1.0, 2.0);
  for (int r = 0; r < probe.rows; ++r) {
    const std::vector<float> f(probe.ptr<float>(r), probe.ptr<float>(r) + probe.cols);
    EXPECT_EQ(kept.colourVerdict(f).shares, source.colourVerdict(f).shares);
  }

  EXPECT_EQ(learn(records(width, false), "checked.json"), 1);
  EXPECT_NE(readText(dir / "learn.log").find("made with a check"), std::string::npos) << readText(dir / "learn.log");
  EXPECT_EQ(learn(records(width - 1, true), "narrow.json"), 1);
  EXPECT_NE(readText(dir / "learn.log").find("check features, the configuration's colour model gives"), std::string::npos)
      << readText(dir / "learn.log");
  EXPECT_EQ(learn("{\"config\": \"c --without-check\", \"pairs\": [{\"seed\": 5, \"objects\": [{\"name\": [1]}]}]}",
                  "bad_name.json"),
            1);
  EXPECT_NE(readText(dir / "learn.log").find("bad_name.json: seed 5: malformed record"), std::string::npos)
      << readText(dir / "learn.log");
  EXPECT_EQ(learn("{\"pairs\": 3}", "no_pairs.json"), 1);
  EXPECT_NE(readText(dir / "learn.log").find("no \"pairs\" list"), std::string::npos) << readText(dir / "learn.log");
  EXPECT_EQ(learn("{\"config\": \"c --without-check --swapped\", \"pairs\": []}", "swapped.json"), 1);
  EXPECT_NE(readText(dir / "learn.log").find("swapped.json: made with --swapped"), std::string::npos)
      << readText(dir / "learn.log");
  EXPECT_EQ(learn("{\"config\": [1], \"pairs\": []}", "list_config.json"), 1);
  EXPECT_NE(readText(dir / "learn.log").find("list_config.json: malformed records (\"config\" is not the command line"),
            std::string::npos)
      << readText(dir / "learn.log");
  fs::remove_all(dir);
}

// Both records learners: each problem named (exit 2 for the command line, 1 for a records file) and no model written.
TEST(LearnChecksAndShapes, BadRecordsAndOutputsAreNamed) {
  const fs::path dir = fs::temp_directory_path() / ("records_learners_test_" + std::to_string(::getpid()));
  fs::create_directories(dir / "folder");
  const DetectorConfig base = loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml");
  const std::string good = (dir / "good.json").string();
  std::ofstream(good) << records(checkFeatureNames(base.learned.model->colours()).size(), true);
  fs::copy_file(good, dir / "copy.json");
  const std::string model = (dir / "model.yml.gz").string();
  const struct {
    std::string args;
    int status;
    std::string named;
  } cases[] = {
      {"--out " + model + " " + (dir / "folder").string(), 1, (dir / "folder").string() + ": cannot read the records file: a folder, not a file"},
      {"--out " + model + " " + (dir / "absent.json").string(), 1,
       (dir / "absent.json").string() + ": cannot read the records file: No such file or directory"},
      {"--out " + model + " " + good + " " + (dir / "." / "good.json").string(), 2, "good.json is given twice (also as " + good},
      // A copy under another name: its records would be learnt twice as well.
      {"--out " + model + " " + good + " " + (dir / "copy.json").string(), 2,
       (dir / "copy.json").string() + " holds the same records as " + good},
      {"--out " + (dir / "folder").string() + " " + good, 2, "--out " + (dir / "folder").string() + " is a folder: give the"},
      {"--out " + (dir / "missing" / "m.yml.gz").string() + " " + good, 2, "is not a writable folder"},
      // The output one of the records: it would be overwritten (a probe found both learners did so).
      {"--out " + (dir / "." / "good.json").string() + " " + good, 2, "is also a records file to learn from"},
  };
  // The two learners' command lines before their own options (learn_checks reads the detector's colours).
  const std::string learners[] = {std::string(UWS_LEARN_CHECKS) + " --config " UWS_SOURCE_DIR "/config/detector.yaml",
                                  UWS_LEARN_SHAPES};
  for (const std::string& learner : learners) {
    for (const auto& c : cases) {
      EXPECT_EQ(runTool(learner + " " + c.args, dir / "learn.log"), c.status) << learner << " " << c.args;
      const std::string log = readText(dir / "learn.log");
      EXPECT_NE(log.find(c.named), std::string::npos) << learner << " " << c.args << ": " << log;
      EXPECT_FALSE(fs::exists(model)) << learner << " " << c.args;
    }
  }
  EXPECT_EQ(readText(good), records(checkFeatureNames(base.learned.model->colours()).size(), true)) << "a records file kept";
  // A shape feature that is no number: a malformed record, named with its file and pair.
  std::string row = "[\"x\"";
  for (int i = 1; i < kShapeFeatureCount; ++i) row += ", 0.5";
  std::ofstream(dir / "bad_shape.json")
      << "{\"pairs\": [{\"seed\": 9, \"objects\": [{\"eligible\": true, \"found\": true, \"shape\": \"sphere\", "
         "\"detected\": {\"shape_features\": " + row + "]}}]}]}";
  EXPECT_EQ(runTool(std::string(UWS_LEARN_SHAPES) + " --out " + model + " " + (dir / "bad_shape.json").string(),
                    dir / "learn.log"),
            1);
  EXPECT_NE(readText(dir / "learn.log").find("bad_shape.json: seed 9: malformed record"), std::string::npos)
      << readText(dir / "learn.log");
  // A feature written .nan or .inf (evaluate_detector writes null for what it could not compute): refused by both.
  row = "[.nan";
  for (int i = 1; i < kShapeFeatureCount; ++i) row += ", 0.5";
  std::ofstream(dir / "nan_shape.json")
      << "{\"pairs\": [{\"seed\": 9, \"objects\": [{\"eligible\": true, \"found\": true, \"shape\": \"sphere\", "
         "\"detected\": {\"shape_features\": " + row + "]}}]}]}";
  std::string nan_checks = records(checkFeatureNames(base.learned.model->colours()).size(), true);
  nan_checks.replace(nan_checks.find("[0.000000"), 9, "[-.inf");
  std::ofstream(dir / "nan_checks.json") << nan_checks;
  for (const auto& [learner, file] : {std::make_pair(learners[0], "nan_checks.json"),
                                      std::make_pair(learners[1], "nan_shape.json")}) {
    EXPECT_EQ(runTool(learner + " --out " + model + " " + (dir / file).string(), dir / "learn.log"), 1) << learner;
    const std::string log = readText(dir / "learn.log");
    EXPECT_NE(log.find(std::string(file) + ": seed "), std::string::npos) << log;
    EXPECT_NE(log.find("not a finite number"), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(model)) << learner;
  }
  // A pair that is no map at all.
  std::ofstream(dir / "scalar.json") << "{\"config\": \"c --without-check\", \"pairs\": [3]}";
  for (const std::string& learner : learners) {
    const std::string command = learner + " --out " + model;
    EXPECT_EQ(runTool(command + " " + (dir / "scalar.json").string(), dir / "learn.log"), 1) << command;
    EXPECT_NE(readText(dir / "learn.log").find("scalar.json: seed ?: malformed record (a pair is not a map)"),
              std::string::npos)
        << readText(dir / "learn.log");
  }
  // A list that is no list (iterating it would find nothing, silently).
  std::ofstream(dir / "objects_text.json") << "{\"config\": \"c --without-check\", \"pairs\": [{\"seed\": 4, \"objects\": \"x\"}]}";
  for (const std::string& learner : learners) {
    const std::string command = learner + " --out " + model + " " + (dir / "objects_text.json").string();
    EXPECT_EQ(runTool(command, dir / "learn.log"), 1) << command;
    EXPECT_NE(readText(dir / "learn.log").find("objects_text.json: seed 4: malformed record (\"objects\" is not a list)"),
              std::string::npos)
        << readText(dir / "learn.log");
  }
  // A flag that is neither true nor false (it would have dropped the object without a word), and two records files
  // joined into one (only the first would have been read).
  std::ofstream(dir / "maybe.json")
      << "{\"config\": \"c --without-check\", \"pairs\": [{\"seed\": 6, \"objects\": [{\"name\": \"a\", "
         "\"eligible\": \"maybe\", \"found\": true, \"designated\": true}]}]}";
  // A bad flag after one that drops the object (learn_shapes reads eligible first, learn_checks found): named all the
  // same.
  std::ofstream(dir / "late_flag_shapes.json")
      << "{\"config\": \"c --without-check\", \"pairs\": [{\"seed\": 8, \"objects\": [{\"name\": \"a\", "
         "\"eligible\": false, \"found\": \"maybe\", \"designated\": true}]}]}";
  std::ofstream(dir / "late_flag_checks.json")
      << "{\"config\": \"c --without-check\", \"pairs\": [{\"seed\": 8, \"objects\": [{\"name\": \"a\", "
         "\"found\": false, \"designated\": true, \"eligible\": \"maybe\"}]}]}";
  std::ofstream(dir / "joined.json") << readText(good) << "\n" << readText(good);
  std::ofstream(dir / "twice.json")
      << "{\"config\": \"c --without-check\", \"pairs\": [{\"seed\": 7, \"objects\": [{\"name\": \"a\", "
         "\"eligible\": false, \"eligible\": true}]}]}";
  for (const std::string& learner : learners) {
    const std::string command = learner + " --out " + model + " ";
    EXPECT_EQ(runTool(command + (dir / "maybe.json").string(), dir / "learn.log"), 1) << command;
    EXPECT_NE(readText(dir / "learn.log").find("maybe.json: seed 6: malformed record"), std::string::npos)
        << readText(dir / "learn.log");
    EXPECT_NE(readText(dir / "learn.log").find("\"eligible\" is neither true nor false"), std::string::npos)
        << readText(dir / "learn.log");
    const bool shapes = learner.find("learn_shapes") != std::string::npos;
    EXPECT_EQ(runTool(command + (dir / (shapes ? "late_flag_shapes.json" : "late_flag_checks.json")).string(),
                      dir / "learn.log"),
              1)
        << command;
    EXPECT_NE(readText(dir / "learn.log").find(shapes ? "\"found\" is neither" : "\"eligible\" is neither"),
              std::string::npos)
        << readText(dir / "learn.log");
    EXPECT_EQ(runTool(command + (dir / "joined.json").string(), dir / "learn.log"), 1) << command;
    EXPECT_NE(readText(dir / "learn.log").find("joined.json: 2 records documents one after the other"),
              std::string::npos)
        << readText(dir / "learn.log");
    EXPECT_EQ(runTool(command + (dir / "twice.json").string(), dir / "learn.log"), 1) << command;
    EXPECT_NE(readText(dir / "learn.log").find("twice.json: keys given twice"), std::string::npos)
        << readText(dir / "learn.log");
  }
  // learn_checks' configuration is part of its command line: a missing one exits 2, as a bad option does.
  EXPECT_EQ(runTool(std::string(UWS_LEARN_CHECKS) + " --config /nonexistent.yaml --out " + model + " " + good,
                    dir / "learn.log"),
            2);
  EXPECT_NE(readText(dir / "learn.log").find("/nonexistent.yaml"), std::string::npos) << readText(dir / "learn.log");
  // Records with nothing to learn from: the trainer's refusal named with the file and the count.
  const std::string empty = (dir / "empty.json").string();
  std::ofstream(empty) << "{\"config\": \"c --without-check\", \"pairs\": []}";
  for (const std::string& learner : learners) {
    const std::string command = learner + " --out " + model;
    EXPECT_EQ(runTool(command + " " + empty, dir / "learn.log"), 1) << command;
    const std::string log = readText(dir / "learn.log");
    EXPECT_TRUE(log.find(empty + ": 0 objects to learn from: ShapeModel::train: no samples of") != std::string::npos ||
                log.find(empty + ": 0 detections to learn from: DetectionCheck::train: no background samples") !=
                    std::string::npos)
        << command << ": " << log;
    EXPECT_FALSE(fs::exists(model)) << command;
  }
  fs::remove_all(dir);
}
