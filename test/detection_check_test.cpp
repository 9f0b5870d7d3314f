// SPDX-License-Identifier: BSD-3-Clause
// The check after stereo (detection_check.h): its features, its configuration, and what it does to detections.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <fstream>
#include <memory>
#include <sstream>
#include <utility>
#include <string>

#include "config_test_helpers.h"
#include "underwater_stereo/detection/blob_proposals.h"
#include "underwater_stereo/detection/detection_check.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/sim/renderer.h"

using namespace underwater_stereo;

namespace {

DetectorConfig defaultConfig() { return loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml"); }

/// Samples over `colours` that name every row like `rows` `label` (-1: background), with each other class learnt
/// from rows far from them (a model must have seen every class). Every row is given kCopies times: boosted trees
/// split only where 10 samples reach a node.
std::pair<cv::Mat, std::vector<int>> samplesNaming(const cv::Mat& rows, int label, const std::vector<std::string>& colours) {
  constexpr int kCopies = 10;
  cv::Mat samples;
  std::vector<int> labels;
  for (int copy = 0; copy < kCopies; ++copy) {
    samples.push_back(rows);
    labels.insert(labels.end(), rows.rows, label);
    for (int k = -1; k < static_cast<int>(colours.size()); ++k) {
      if (k == label) continue;
      samples.push_back(cv::Mat(1, rows.cols, CV_32F, cv::Scalar(1e6)));
      labels.push_back(k);
    }
  }
  return {samples, labels};
}

/// A check over `colours` learnt from samplesNaming(rows, label, colours).
std::shared_ptr<const DetectionCheck> checkNaming(const cv::Mat& rows, int label, const std::vector<std::string>& colours) {
  const auto [samples, labels] = samplesNaming(rows, label, colours);
  return std::make_shared<const DetectionCheck>(DetectionCheck::train(samples, labels, colours, checkTraining()));
}

/// The 640x400 pool of two buoys (red, green), rendered as BGR.
sim::Scene smallPool() {
  sim::Scene scene = sim::loadSceneFile(UWS_SOURCE_DIR "/test/scenes/small_pool.yaml");
  scene.sensor.encoding = "bgr8";
  return scene;
}

/// Each detection's check features as one row, the rows checkNaming learns from.
cv::Mat checkRows(const DetectionResult& result) {
  cv::Mat rows;
  for (const Detection& d : result.objects) rows.push_back(cv::Mat(d.check_features, true).reshape(1, 1));
  return rows;
}

/// The index of `name` among `colours` (colours.size() when it is not one of them).
int indexOf(const std::vector<std::string>& colours, const std::string& name) {
  return static_cast<int>(std::find(colours.begin(), colours.end(), name) - colours.begin());
}

}  // namespace

TEST(DetectionCheck, FeaturesAreTheColourSearchsThenWhatStereoMeasured) {
  const std::vector<std::string> names = checkFeatureNames({"red", "green"});
  ASSERT_EQ(names.size(), static_cast<std::size_t>(kBlobFeatureCount) + 3 + 7);
  EXPECT_EQ(names.front(), blobFeatureNames().front());
  EXPECT_EQ(names[kBlobFeatureCount], "share_background");
  EXPECT_EQ(names[kBlobFeatureCount + 2], "share_green");
  EXPECT_EQ(names.back(), "matched_share");
  MeasuredForCheck m;
  m.range_m = 2.5;
  m.largest_size_m = 0.4;
  m.smallest_size_m = 0.0;  // a flat fit: its logarithm stays finite
  m.cut_by_border = true;
  m.fit_rmse_m = 0.025;
  m.matched_share = 0.8;
  const std::vector<float> f = checkFeatures(std::vector<float>(kBlobFeatureCount + 3, 0.5f), m);
  ASSERT_EQ(f.size(), names.size());
  EXPECT_FLOAT_EQ(f[kBlobFeatureCount + 3], 2.5f);
  EXPECT_NEAR(f[kBlobFeatureCount + 4], std::log(0.4), 1e-6);
  EXPECT_TRUE(std::isfinite(f[kBlobFeatureCount + 5]));
  EXPECT_FLOAT_EQ(f[kBlobFeatureCount + 7], 1.f);
  EXPECT_NEAR(f[kBlobFeatureCount + 8], 0.01, 1e-6) << "the fit's residual as a share of the range";
  EXPECT_THROW(checkFeatures({}, m), std::invalid_argument) << "a candidate no colour model found";
}

TEST(DetectionCheck, ItTurnsDownWhatItTakesForBackgroundAfterStereo) {
  const sim::Renderer renderer(smallPool());
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  DetectorConfig config = defaultConfig();
  const std::vector<std::string>& colours = config.learned.model->colours();
  const DetectionResult plain = Detector(config, renderer.calibration()).detect(pair.left, pair.right);
  ASSERT_EQ(plain.objects.size(), 2U);
  for (const Detection& d : plain.objects) ASSERT_EQ(d.check_features.size(), checkFeatureNames(colours).size());
  const cv::Mat rows = checkRows(plain);

  config.learned.check = checkNaming(rows, -1, colours);
  const DetectionResult background = Detector(config, renderer.calibration()).detect(pair.left, pair.right);
  EXPECT_TRUE(background.objects.empty());
  int turned_down = 0;
  for (const Rejection& r : background.rejected) {
    if (r.stage != RejectionStage::kCheckAfterStereo) continue;
    ++turned_down;
    EXPECT_NE(r.reason.find("check_min_confidence"), std::string::npos) << r.reason;
  }
  EXPECT_EQ(turned_down, 2);

  // A check that takes them for orange objects: at check_rename_margin 1 they keep the colour model's colours.
  const int orange = indexOf(colours, "orange");
  ASSERT_LT(orange, static_cast<int>(colours.size()));
  config.learned.check = checkNaming(rows, orange, colours);
  config.learned.check_rename_margin = 1.0;
  const DetectionResult kept = Detector(config, renderer.calibration()).detect(pair.left, pair.right);
  ASSERT_EQ(kept.objects.size(), 2U);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(kept.objects[k].colour, plain.objects[k].colour) << "the check does not name colours at margin 1";
    EXPECT_EQ(kept.objects[k].position_m, plain.objects[k].position_m);
    // Its confidence weighs the check's object score (the default check's for `plain`).
    const std::vector<float>& f = kept.objects[k].check_features;
    EXPECT_NEAR(kept.objects[k].confidence / plain.objects[k].confidence,
                config.learned.check->objectScore(f) / defaultConfig().learned.check->objectScore(f), 1e-6);
    EXPECT_LE(kept.objects[k].confidence, 1.0);
  }
  // At the default margin its colour replaces the colour model's (red and green: the check is sure of orange),
  // and nothing else changes.
  config.learned.check_rename_margin = LearnedColourConfig{}.check_rename_margin;
  const DetectionResult renamed = Detector(config, renderer.calibration()).detect(pair.left, pair.right);
  ASSERT_EQ(renamed.objects.size(), 2U);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_NE(plain.objects[k].colour, "orange");
    EXPECT_EQ(renamed.objects[k].colour, "orange") << plain.objects[k].colour << " named by the check";
    EXPECT_EQ(renamed.objects[k].position_m, plain.objects[k].position_m);
    EXPECT_EQ(renamed.objects[k].confidence, kept.objects[k].confidence);
  }
  // Unless orange is not designated in this configuration: then the colour model's colour stays.
  DetectorConfig without_orange = config;
  without_orange.colours.classes.erase(std::remove_if(without_orange.colours.classes.begin(),
                                                      without_orange.colours.classes.end(),
                                                      [](const ColourClass& c) { return c.name == "orange"; }),
                                       without_orange.colours.classes.end());
  const DetectionResult undesignated = Detector(without_orange, renderer.calibration()).detect(pair.left, pair.right);
  ASSERT_EQ(undesignated.objects.size(), 2U);
  for (std::size_t k = 0; k < 2; ++k) EXPECT_EQ(undesignated.objects[k].colour, plain.objects[k].colour);
}

// A dark frame (darker than quality.enhance_below), here one searched at search_scale (640x400: dark_search_width_px
// would be finer): the check learnt the colours of few such frames and misnamed them, so it does not rename there.
TEST(DetectionCheck, ItDoesNotNameColoursInADarkFrame) {
  sim::Scene scene = smallPool();
  scene.light.exposure = 0.01;  // mean luma ~15
  const sim::Renderer renderer(scene);
  const sim::RenderedPair pair = renderer.render(0.0, 0);
  DetectorConfig config = defaultConfig();
  const DetectionResult plain = Detector(config, renderer.calibration()).detect(pair.left, pair.right);
  ASSERT_TRUE(plain.quality.enhanced);
  EXPECT_EQ(plain.search_scale, config.search_scale);
  ASSERT_FALSE(plain.objects.empty());
  const std::vector<std::string>& colours = config.learned.model->colours();
  config.learned.check = checkNaming(checkRows(plain), indexOf(colours, "orange"), colours);
  const DetectionResult checked = Detector(config, renderer.calibration()).detect(pair.left, pair.right);
  ASSERT_EQ(checked.objects.size(), plain.objects.size());
  for (std::size_t k = 0; k < plain.objects.size(); ++k) {
    EXPECT_NE(plain.objects[k].colour, "orange");
    EXPECT_EQ(checked.objects[k].colour, plain.objects[k].colour);
  }
}

TEST(DetectionCheck, TheConfigurationLoadsItOverItsColourModelOnly) {
  const std::string model = UWS_SOURCE_DIR "/config/detector.colour_model.yml.gz";
  const std::vector<std::string> colours = ColourModel::load(model).colours();
  const cv::Mat row(1, static_cast<int>(checkFeatureNames(colours).size()), CV_32F, cv::Scalar(0));
  checkNaming(row, -1, colours)->save(::testing::TempDir() + "check.yml.gz");
  // A check of an earlier build (a forest alone) is refused: it has no boosted trees.
  ColourModelTraining without_boosted = checkTraining();
  without_boosted.boosted.trees = 0;
  const auto [samples, labels] = samplesNaming(row, -1, colours);
  ColourModel::train(samples, labels, colours, without_boosted, checkFeatureNames(colours))
      .save(::testing::TempDir() + "forest_check.yml.gz");
  const std::string head = "colours: [{name: red}, {name: orange}, {name: yellow}, {name: green}]\n"
                           "candidates: {source: learned}\n";
  const DetectorConfig ok = parseDetectorConfig(
      YAML::Load(head + "colour_model: {file: " + model + ", check_file: check.yml.gz, check_min_confidence: 0.5}"),
      ::testing::TempDir());
  ASSERT_TRUE(ok.learned.check);
  EXPECT_DOUBLE_EQ(ok.learned.check_min_confidence, 0.5);

  const std::string without_model = refusalOf(head + "colour_model: {check_file: check.yml.gz}");
  EXPECT_NE(without_model.find("colour_model.check_file: the check reads the colour model's votes"), std::string::npos)
      << without_model;
  const std::string not_learned = refusalOf(
      "colours: [{name: red, hue: [170, 10]}]\ncandidates: {source: colour_mask}\n"
      "colour_model: {file: " + model + ", check_file: check.yml.gz}");
  EXPECT_NE(not_learned.find("candidates.source is not learned"), std::string::npos) << not_learned;
  const std::string bad_share = refusalOf(head + "colour_model: {file: " + model + ", check_file: check.yml.gz, "
                                                 "check_min_confidence: 0}");
  EXPECT_NE(bad_share.find("colour_model.check_min_confidence must be in [0.01, 1]"), std::string::npos) << bad_share;
  // A check learnt over another colour model's colours reads other votes: refused by its feature names.
  const std::vector<std::string> others{"red", "green"};
  const cv::Mat other_row(1, static_cast<int>(checkFeatureNames(others).size()), CV_32F, cv::Scalar(0));
  checkNaming(other_row, -1, others)->save(::testing::TempDir() + "other_check.yml.gz");
  const std::string other = refusalOf(head + "colour_model: {file: " + model + ", check_file: other_check.yml.gz}");
  EXPECT_NE(other.find("colour_model.check_file: check model"), std::string::npos) << other;
  EXPECT_NE(other.find("made for other features"), std::string::npos) << other;
  const std::string forest_only = refusalOf(head + "colour_model: {file: " + model + ", check_file: forest_check.yml.gz}");
  EXPECT_NE(forest_only.find("no boosted trees"), std::string::npos) << forest_only;
}

// A check file whose boosted trees split on a feature it does not have, or vote outside gentle AdaBoost's [-1, 1], is
// refused with the file named (OpenCV would read out of bounds, or the object score would leave 0-1).
TEST(DetectionCheck, ACorruptCheckFileIsRefusedNamingIt) {
  const std::vector<std::string> colours{"red", "green"};
  const int width = static_cast<int>(checkFeatureNames(colours).size());
  cv::Mat rows(2, width, CV_32F);
  cv::randu(rows, 0.0, 1.0);
  const std::string good = ::testing::TempDir() + "check_plain.yml";
  checkNaming(rows, 0, colours)->save(good);
  EXPECT_NO_THROW(DetectionCheck::load(good, colours));
  std::stringstream text;
  text << std::ifstream(good).rdbuf();
  const std::string saved = text.str();
  const std::size_t object = saved.find("object:");
  ASSERT_NE(object, std::string::npos);
  auto refusal = [&](const std::string& key, const std::string& bad) {
    std::string corrupt = saved;
    const std::size_t at = corrupt.find(key, object);
    if (at == std::string::npos) return std::string("no ") + key + " in the boosted trees";
    corrupt.replace(at, corrupt.find_first_of(",\n", at) - at, bad);
    const std::string path = ::testing::TempDir() + "check_corrupt.yml";
    std::ofstream(path) << corrupt;
    try {
      DetectionCheck::load(path, colours);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::string split = refusal("var:", "var:" + std::to_string(width));
  EXPECT_NE(split.find("check model " + ::testing::TempDir() + "check_corrupt.yml: boosted trees: tree 0 node 0 splits on "
                       "feature"), std::string::npos) << split;
  const std::string vote = refusal("value:", "value: 7.5");
  EXPECT_NE(vote.find("outside [-1, 1]"), std::string::npos) << vote;
  EXPECT_THROW(DetectionCheck::load(::testing::TempDir() + "no_such_check.yml", colours), std::invalid_argument);
}
