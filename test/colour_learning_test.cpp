// SPDX-License-Identifier: BSD-3-Clause
// Learning colours from labelled frames: a known colour model is recovered from synthetic frames; bad labels
// are named with file and box; a learnt model loads through the config validator.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <yaml-cpp/yaml.h>

#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>

#include "config_test_helpers.h"
#include "underwater_stereo/detection/colour_learning.h"
#include "underwater_stereo/detection/detector.h"

using namespace underwater_stereo;

namespace {

/// A 480x360 frame of water (random colour) with buoys: red and green (labelled) and white (not: background).
LabelledFrame syntheticFrame(unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const cv::Vec3d water(60 + 120 * u(rng), 110 + 60 * u(rng), 40 + 60 * u(rng));
  LabelledFrame f;
  f.name = "synthetic_" + std::to_string(seed);
  f.image = cv::Mat(360, 480, CV_8UC3);
  cv::randn(f.image, cv::Scalar(water[0], water[1], water[2]), cv::Scalar(3, 3, 3));
  const struct {
    const char* label;
    cv::Vec3d colour;
  } kinds[] = {{"buoy_red", {30, 40, 210}}, {"buoy_green", {40, 200, 50}}, {"", {235, 235, 235}}};
  std::vector<cv::Rect> used;
  for (int k = 0; k < 4; ++k) {
    const auto& kind = kinds[k % 3];
    const int r = 10 + static_cast<int>(25 * u(rng));
    const cv::Point c(r + static_cast<int>((480 - 2 * r) * u(rng)), r + static_cast<int>((360 - 2 * r) * u(rng)));
    const cv::Rect box(c.x - r, c.y - r, 2 * r + 1, 2 * r + 1);
    bool overlaps = false;
    for (const cv::Rect& o : used) overlaps |= (o & (box + cv::Size(20, 20) - cv::Point(10, 10))).area() > 0;
    if (overlaps) continue;
    used.push_back(box);
    const double t = 0.3 + 0.6 * u(rng);  // transmission: near and far
    cv::Scalar seen;
    for (int ch = 0; ch < 3; ++ch) seen[ch] = kind.colour[ch] * t + water[ch] * (1 - t);
    cv::circle(f.image, c, r, seen, cv::FILLED);
    if (*kind.label) f.labels.push_back({kind.label, box});
  }
  cv::GaussianBlur(f.image, f.image, cv::Size(3, 3), 0);
  return f;
}

DetectorConfig baseConfig() {
  DetectorConfig c = loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml");
  c.search_scale = 1.0;
  c.candidates.min_area_px = 60;
  return c;
}

LearningOptions options() {
  LearningOptions o;
  o.colours = {"red", "green"};
  o.augment = 1;
  o.training.trees = 40;
  return o;
}

/// What `f` throws as std::invalid_argument, or "no error".
std::string messageOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

ColourModel learnt(const std::vector<LabelledFrame>& frames, const LearningOptions& o) {
  const Detector proposer(proposerConfig(baseConfig()));
  std::vector<FrameSamples> samples;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    samples.push_back(samplesOf(frames[i], proposer, o, static_cast<unsigned>(i + 1)));
  }
  std::vector<const FrameSamples*> parts;
  for (const FrameSamples& s : samples) parts.push_back(&s);
  return learnColourModel(parts, o);
}

}  // namespace

TEST(ColourLearning, RecoversAKnownColourModel) {
  std::vector<LabelledFrame> train, test;
  for (unsigned s = 0; s < 40; ++s) train.push_back(syntheticFrame(s));
  for (unsigned s = 1000; s < 1020; ++s) test.push_back(syntheticFrame(s));
  const LearningOptions o = options();
  checkLabels(train, o);
  const auto model = std::make_shared<const ColourModel>(learnt(train, o));
  const LearningScore score_ = score(Detector(learnedConfig(baseConfig(), "in memory", model, o)), test, o);
  SCOPED_TRACE("seeds 1000-1019");
  EXPECT_GE(score_.found[0], 0.9 * score_.labelled[0]) << "red";
  EXPECT_GE(score_.found[1], 0.9 * score_.labelled[1]) << "green";
  EXPECT_EQ(score_.confusion[0][1] + score_.confusion[1][0], 0) << "red and green confused";
  EXPECT_LE(score_.false_detections, 0.2 * score_.frames) << "white buoys or water reported";
}

// With boosted trees the model's confidence is their object score (0.5 where their votes even out) while the forest
// names the colour; they are stored in the model file and read back with it, and corrupt trees are refused naming it.
TEST(ColourLearning, BoostedTreesDecideAndTravelWithTheModelFile) {
  std::vector<LabelledFrame> train, test;
  for (unsigned s = 0; s < 40; ++s) train.push_back(syntheticFrame(s));
  for (unsigned s = 1000; s < 1020; ++s) test.push_back(syntheticFrame(s));
  LearningOptions o = options();
  o.training.boosted = {100, 3};
  const ColourModel model = learnt(train, o);
  ASSERT_TRUE(model.hasObjectTrees());
  DetectorConfig base = baseConfig();
  base.learned.min_confidence = 0.5;
  const LearningScore score_ =
      score(Detector(learnedConfig(base, "in memory", std::make_shared<const ColourModel>(model), o)), test, o);
  SCOPED_TRACE("seeds 1000-1019");
  EXPECT_GE(score_.found[0], 0.9 * score_.labelled[0]) << "red";
  EXPECT_GE(score_.found[1], 0.9 * score_.labelled[1]) << "green";
  EXPECT_EQ(score_.confusion[0][1] + score_.confusion[1][0], 0) << "red and green confused";
  EXPECT_LE(score_.false_detections, 0.2 * score_.frames) << "white buoys or water reported";

  const std::string path = ::testing::TempDir() + "boosted.colour_model.yml";
  model.save(path);
  const ColourModel read = ColourModel::load(path);
  ASSERT_TRUE(read.hasObjectTrees());
  cv::Mat probe(16, static_cast<int>(blobFeatureNames().size()), CV_32F);
  cv::randu(probe, -1.0, 2.0);
  const std::vector<ColourVerdict> before = model.classify(probe), after = read.classify(probe);
  for (int r = 0; r < probe.rows; ++r) {
    EXPECT_EQ(after[r].colour, before[r].colour);
    EXPECT_DOUBLE_EQ(after[r].confidence, before[r].confidence);
    if (before[r].colour >= 0) {
      EXPECT_DOUBLE_EQ(before[r].confidence, model.objectScore(probe.ptr<float>(r)));
    }
  }
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  std::string corrupt = text.str();
  const std::size_t vote = corrupt.find("value:", corrupt.find("object:"));
  ASSERT_NE(vote, std::string::npos);
  corrupt.replace(vote, corrupt.find_first_of(",\n", vote) - vote, "value: 7.5");
  std::ofstream(path) << corrupt;
  const std::string refused = messageOf([&] { ColourModel::load(path); });
  EXPECT_NE(refused.find("colour model " + path + ": boosted trees: a node votes 7.5"), std::string::npos) << refused;
  // A gzipped model cut short (OpenCV would read what is left without a word) is refused; whole, it is read.
  const std::string gz = ::testing::TempDir() + "boosted.colour_model.yml.gz";
  model.save(gz);
  EXPECT_TRUE(ColourModel::load(gz).hasObjectTrees());
  std::stringstream packed;
  packed << std::ifstream(gz, std::ios::binary).rdbuf();
  for (const std::size_t cut : {std::size_t{12}, packed.str().size() / 2}) {
    std::ofstream(gz, std::ios::binary) << packed.str().substr(0, packed.str().size() - cut);
    const std::string short_file = messageOf([&] { ColourModel::load(gz); });
    EXPECT_NE(short_file.find("colour model " + gz + ": unreadable (gzip: unexpected end of file"), std::string::npos)
        << "cut " << cut << ": " << short_file;
  }
  std::string flipped = packed.str();  // whole, but corrupt in the middle: zlib's check names it
  for (std::size_t i = flipped.size() / 2; i < flipped.size() / 2 + 16; ++i) flipped[i] = static_cast<char>(flipped[i] ^ 0x5a);
  std::ofstream(gz, std::ios::binary) << flipped;
  const std::string corrupt_file = messageOf([&] { ColourModel::load(gz); });
  EXPECT_NE(corrupt_file.find("colour model " + gz + ": unreadable (gzip: "), std::string::npos) << corrupt_file;
  std::ofstream(gz, std::ios::binary) << packed.str() << "\n\n";  // bytes after the last member are ignored, as gzread does
  EXPECT_TRUE(ColourModel::load(gz).hasObjectTrees());

  o.training.boosted.depth = 0;
  const std::string bad = messageOf([&] { learnt(train, o); });
  EXPECT_NE(bad.find("boosted_depth must be in [1, 20] (or 0: none)"), std::string::npos) << bad;
}

TEST(ColourLearning, ScoresAtSeveralThresholdsAsDetectorsSetToEach) {
  std::vector<LabelledFrame> train, test;
  for (unsigned s = 0; s < 20; ++s) train.push_back(syntheticFrame(s));
  for (unsigned s = 2000; s < 2015; ++s) test.push_back(syntheticFrame(s));
  const LearningOptions o = options();
  const auto model = std::make_shared<const ColourModel>(learnt(train, o));
  const std::vector<double> thresholds{0.2, 0.4, 0.6, 0.8};
  DetectorConfig c = learnedConfig(baseConfig(), "in memory", model, o);
  c.learned.min_confidence = thresholds.front();
  const std::vector<LearningScore> swept = scoreAt(Detector(c), test, o, thresholds);
  ASSERT_EQ(swept.size(), thresholds.size());
  for (std::size_t t = 0; t < thresholds.size(); ++t) {
    c.learned.min_confidence = thresholds[t];
    const LearningScore alone = score(Detector(c), test, o);
    EXPECT_EQ(swept[t].found, alone.found) << "min_confidence " << thresholds[t];
    EXPECT_EQ(swept[t].false_detections, alone.false_detections) << "min_confidence " << thresholds[t];
    EXPECT_EQ(swept[t].confusion, alone.confusion) << "min_confidence " << thresholds[t];
  }
  EXPECT_THROW(scoreAt(Detector(c), test, o, {0.6, 0.4}), std::invalid_argument) << "not ascending";
  EXPECT_THROW(scoreAt(Detector(c), test, o, {0.5}), std::invalid_argument) << "under the detector's own threshold";
}

TEST(ColourLearning, LearntModelRoundTripsThroughTheConfigValidator) {
  std::vector<LabelledFrame> train;
  for (unsigned s = 0; s < 20; ++s) train.push_back(syntheticFrame(s));
  const LearningOptions o = options();
  const std::string model_path = ::testing::TempDir() + "roundtrip.colour_model.yml.gz";
  learnt(train, o).save(model_path);
  const DetectorConfig ok = parseDetectorConfig(
      YAML::Load("colours: [{name: red}, {name: green}]\ncandidates: {source: learned}\n"
                 "colour_model: {file: roundtrip.colour_model.yml.gz, min_confidence: 0.4}"),
      ::testing::TempDir());
  ASSERT_TRUE(ok.learned.model);
  EXPECT_EQ(ok.learned.model->colours(), o.colours);
  EXPECT_DOUBLE_EQ(ok.learned.min_confidence, 0.4);
  const DetectorConfig per_colour = parseDetectorConfig(
      YAML::Load("colours: [{name: red, min_confidence: 0.55}, {name: green}]\ncandidates: {source: learned}\n"
                 "colour_model: {file: roundtrip.colour_model.yml.gz}"),
      ::testing::TempDir());
  EXPECT_DOUBLE_EQ(per_colour.colours.classes[0].min_confidence, 0.55);
  EXPECT_DOUBLE_EQ(per_colour.colours.classes[1].min_confidence, 0.0) << "the colour model's";
  const DetectorConfig window_only = parseDetectorConfig(
      YAML::Load("colours: [{name: red}, {name: green}]\ncandidates: {source: learned}\n"
                 "colour_model: {file: roundtrip.colour_model.yml.gz, water_object_level: 0}"),
      ::testing::TempDir());
  EXPECT_DOUBLE_EQ(window_only.learned.water.object_level, 0.0);
  const std::string negative_level =
      refusalOf("colours: [{name: red}, {name: green}]\ncandidates: {source: learned}\n"
                "colour_model: {file: roundtrip.colour_model.yml.gz, water_object_level: -3}");
  ASSERT_FALSE(negative_level.empty()) << "a negative water_object_level was accepted";
  EXPECT_NE(negative_level.find("colour_model.water_object_level must be in [0, 1000]"), std::string::npos)
      << "named by its key in the file: " << negative_level;
  const std::string bad_window = refusalOf("colours: [{name: red}, {name: green}]\ncandidates: {source: learned}\n"
                                           "colour_model: {file: roundtrip.colour_model.yml.gz, background_scale: 2, "
                                           "levels: [], max_proposals: 0, piece_step: -1}");
  for (const char* key : {"colour_model.background_scale must", "colour_model.levels: 1 to 16", "colour_model.max_proposals must",
                          "colour_model.piece_step must"}) {
    EXPECT_NE(bad_window.find(key), std::string::npos) << key << " not in: " << bad_window;
  }
  const std::string too_sure = refusalOf("colours: [{name: red, min_confidence: 1.5}, {name: green}]\n"
                                         "candidates: {source: learned}\ncolour_model: {file: roundtrip.colour_model.yml.gz}");
  ASSERT_FALSE(too_sure.empty()) << "a per-colour min_confidence of 1.5 was accepted";
  EXPECT_NE(too_sure.find("colours[0] (red).min_confidence"), std::string::npos) << too_sure;
  const std::string unlearnt = refusalOf("colours: [{name: red}, {name: orange}]\ncandidates: {source: learned}\n"
                                         "colour_model: {file: roundtrip.colour_model.yml.gz, min_confidence: 2}");
  ASSERT_FALSE(unlearnt.empty()) << "a colour the model has not learnt was accepted";
  EXPECT_NE(unlearnt.find("'orange' is designated but the colour model"), std::string::npos) << unlearnt;
  EXPECT_NE(unlearnt.find("min_confidence"), std::string::npos) << unlearnt;
  EXPECT_THROW(parseDetectorConfig(YAML::Load("colours: [{name: red}]\ncandidates: {source: learned}\n"
                                              "colour_model: {file: missing.yml.gz}"),
                                   ::testing::TempDir()),
               std::invalid_argument);
  EXPECT_THROW(parseDetectorConfig(YAML::Load("colours: [{name: red}]\ncandidates: {source: colour_mask}")),
               std::invalid_argument)
      << "a hue range is needed without a learnt model";
  const std::string not_a_model = writeTemp("not_a_model.yml", "%YAML:1.0\ncolours: [red]\nfeatures: [a, b]\n");
  try {
    ColourModel::load(not_a_model);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(not_a_model), std::string::npos) << e.what();
  }
}

TEST(ColourLearning, BadLabelsAreNamedWithFileAndBox) {
  const std::string head = "<annotation><object><name>buoy_red</name><bndbox>";
  const std::string empty_box = writeTemp("empty.xml", head + "<xmin>10</xmin><ymin>5</ymin><xmax>10</xmax><ymax>9</ymax></bndbox></object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(empty_box); }).find(empty_box + ": object 0 (buoy_red): empty box [10, 5, 10, 9]"), std::string::npos);
  const std::string not_number = writeTemp("nan.xml", head + "<xmin>a</xmin><ymin>5</ymin><xmax>10</xmax><ymax>9</ymax></bndbox></object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(not_number); }).find("<xmin> 'a' is not a number"), std::string::npos);
  const std::string hex = writeTemp("hex.xml", head + "<xmin>0x20C</xmin><ymin>5</ymin><xmax>600</xmax><ymax>9</ymax></bndbox></object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(hex); }).find("<xmin> '0x20C' is not a number"), std::string::npos);
  const std::string unclosed = writeTemp("unclosed.xml", head + "<xmin>1</xmin>");
  EXPECT_NE(messageOf([&] { readVocLabels(unclosed); }).find(unclosed + ": unreadable XML"), std::string::npos);
  const std::string not_voc = writeTemp("not_voc.xml", "hello");
  EXPECT_NE(messageOf([&] { readVocLabels(not_voc); }).find("not a Pascal VOC annotation"), std::string::npos);
  EXPECT_NE(messageOf([&] { readVocLabels(::testing::TempDir() + "absent.xml"); }).find("absent.xml: No such file or directory"), std::string::npos);
  const std::string folder = ::testing::TempDir() + "folder.xml";
  ::mkdir(folder.c_str(), 0700);
  EXPECT_NE(messageOf([&] { readVocLabels(folder); }).find(folder + ": a folder, not a file"), std::string::npos)
      << messageOf([&] { readVocLabels(folder); });
  // XML's own rules: a commented-out object is no object, attributes are allowed, a <part>'s box is the part's.
  const std::string box = "<bndbox><xmin>10</xmin><ymin>5</ymin><xmax>30</xmax><ymax>25</ymax></bndbox>";
  const std::string xml_rules = writeTemp("rules.xml", "<annotation><!-- <object><name>green</name>" + box +
      "</object> --><object id=\"0\"><name> buoy_red </name>" + box + "<part><name>stem</name><bndbox><xmin>1</xmin>"
      "<ymin>1</ymin><xmax>2</xmax><ymax>2</ymax></bndbox></part></object></annotation>");
  const std::vector<LabelBox> labels = readVocLabels(xml_rules);
  ASSERT_EQ(labels.size(), 1U);
  EXPECT_EQ(labels[0].name, "buoy_red");
  EXPECT_EQ(labels[0].box, cv::Rect(10, 5, 20, 20));
  const std::string swallowed = writeTemp("swallowed.xml", "<annotation><object><name>red</name>" + box +
      "<object><name>green</name>" + box + "</object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(swallowed); }).find(swallowed + ": unreadable XML"), std::string::npos)
      << "an unclosed <object> must not swallow the next one";
  const std::string huge = writeTemp("huge.xml", head + "<xmin>1</xmin><ymin>5</ymin><xmax>10</xmax><ymax>3e9</ymax></bndbox></object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(huge); }).find("object 0 (buoy_red): <ymax> 3e9 lies beyond any image"), std::string::npos)
      << messageOf([&] { readVocLabels(huge); });
  const std::string twice = writeTemp("twice.xml", "<annotation><object><name>red</name>" + box +
      "</object><object><name>yellow</name>" + box + "</object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(twice); }).find("object 1 (yellow): box [10, 5, 30, 25] is also object 0's (red)"),
            std::string::npos) << messageOf([&] { readVocLabels(twice); });
  // The same object boxed again a pixel off in another colour: taught as both (the last one winning) unless refused.
  const std::string nearly = writeTemp("nearly.xml", "<annotation><object><name>yellow</name>" + box +
      "</object><object><name>buoy_green</name><bndbox><xmin>10</xmin><ymin>5</ymin><xmax>31</xmax><ymax>25</ymax>"
      "</bndbox></object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(nearly); })
                .find("object 1 (buoy_green): box [10, 5, 31, 25] is nearly object 0's (yellow, [10, 5, 30, 25])"),
            std::string::npos) << messageOf([&] { readVocLabels(nearly); });
  // What a reader would otherwise drop without a word: a second annotation joined on, a second box, name or corner.
  const std::string joined = writeTemp("joined.xml", "<annotation><object><name>red</name>" + box +
      "</object></annotation><annotation><object><name>green</name>" + box + "</object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(joined); }).find(joined + ": a second <annotation> after the <annotation>"),
            std::string::npos) << messageOf([&] { readVocLabels(joined); });
  const std::string two_boxes = writeTemp("two_boxes.xml", "<annotation><object><name>red</name>" + box + box +
      "</object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(two_boxes); }).find("object 0 (red) has two <bndbox>"), std::string::npos)
      << messageOf([&] { readVocLabels(two_boxes); });
  const std::string two_names = writeTemp("two_names.xml", "<annotation><object><name>red</name><name>green</name>" +
      box + "</object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(two_names); }).find("object 0 has two <name>"), std::string::npos)
      << messageOf([&] { readVocLabels(two_names); });
  const std::string two_corners = writeTemp("two_corners.xml", "<annotation><object><name>red</name><bndbox><xmin>10"
      "</xmin><xmin>12</xmin><ymin>5</ymin><xmax>30</xmax><ymax>25</ymax></bndbox></object></annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(two_corners); }).find("object 0 (red) has two <xmin>"), std::string::npos)
      << messageOf([&] { readVocLabels(two_corners); });

  LabelledFrame f;
  f.name = "frame_7.jpg";
  f.image = cv::Mat(100, 100, CV_8UC3, cv::Scalar::all(90));
  f.labels = {{"buoy_red", cv::Rect(90, 90, 20, 20)}, {"gate", cv::Rect(10, 10, 5, 5)}, {"green", cv::Rect(40, 40, 10, 10)}};
  const std::string m = messageOf([&] { checkLabels({f}, options()); });
  EXPECT_NE(m.find("frame_7.jpg: box 0 (buoy_red) [90, 90, 110, 110]: outside the 100x100 image"), std::string::npos) << m;
  EXPECT_NE(m.find("frame_7.jpg: box 1 (gate) [10, 10, 15, 15]: label 'gate' names no designated colour"), std::string::npos) << m;
  // Its one green label, 10 px tall, is beyond the working range (min_label_px 15): it teaches nothing, and is named.
  EXPECT_NE(m.find("colour 'green': no labelled example in 1 frames: its labels are under --min-label-px (15 px tall), "
                   "which teach nothing: frame_7.jpg: box 2 (green) [40, 40, 50, 50]"),
            std::string::npos)
      << m;
  // Zoomed copies (up to 2x nearer) make it 20 px tall: it teaches then; a 5-px label does not even so.
  LearningOptions zoomed = options();
  zoomed.zoom = 1;
  EXPECT_EQ(messageOf([&] { checkLabels({f}, zoomed); }).find("colour 'green'"), std::string::npos);
  f.labels.back().box = cv::Rect(40, 40, 5, 5);
  EXPECT_NE(messageOf([&] { checkLabels({f}, zoomed); }).find("colour 'green': no labelled example"), std::string::npos);
  LearningOptions with_gate = options();
  with_gate.background_labels = {"gate"};
  EXPECT_EQ(colourOfLabel("gate", with_gate), -1);
  EXPECT_EQ(colourOfLabel("green", with_gate), 1);
  EXPECT_EQ(colourOfLabel("buoy_red", with_gate), 0);
  // A background label that names a colour would be learnt as that colour: refused.
  LearningOptions red_as_background = options();
  red_as_background.background_labels = {"buoy_red"};
  const std::vector<std::string> problems = red_as_background.validate();
  ASSERT_EQ(problems.size(), 1U);
  EXPECT_NE(problems[0].find("background label 'buoy_red' names the colour red"), std::string::npos) << problems[0];
  // A colour named twice (or not at all) is refused as such, not as a colour without examples.
  LearningOptions doubled = options();
  doubled.colours = {"red", "green", "red", ""};
  const std::vector<std::string> named_twice = doubled.validate();
  ASSERT_EQ(named_twice.size(), 2U);
  EXPECT_EQ(named_twice[0], "colour 'red' is named twice");
  EXPECT_EQ(named_twice[1], "colour 4 has no name");
}

TEST(ColourLearning, AnAnnotationsDeclaredSizeMustBeItsImages) {
  const std::string object = "<object><name>red</name><bndbox><xmin>10</xmin><ymin>5</ymin><xmax>30</xmax>"
                             "<ymax>25</ymax></bndbox></object>";
  cv::Size declared;
  readVocLabels(writeTemp("sized.xml", "<annotation><size><width>160</width><height>120</height><depth>3</depth>"
                                       "</size>" + object + "</annotation>"), &declared);
  EXPECT_EQ(declared, cv::Size(160, 120));
  readVocLabels(writeTemp("unsized.xml", "<annotation>" + object + "</annotation>"), &declared);
  EXPECT_TRUE(declared.empty());
  readVocLabels(writeTemp("zero.xml", "<annotation><size><width>0</width><height>0</height></size>" + object +
                                      "</annotation>"), &declared);
  EXPECT_TRUE(declared.empty()) << "0 x 0 is how some tools write an unknown size";
  const std::string bad = writeTemp("bad_size.xml", "<annotation><size><width>16O</width><height>120</height></size>" +
                                                    object + "</annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(bad, &declared); }).find(bad + ": <size> <width> '16O' is not a whole number"),
            std::string::npos) << messageOf([&] { readVocLabels(bad, &declared); });
  // A side given twice: which one the tool meant is not known, so the size is not checked against either silently.
  const std::string two_widths = writeTemp("two_widths.xml", "<annotation><size><width>160</width><width>1920</width>"
                                                             "<height>120</height></size>" + object + "</annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(two_widths, &declared); }).find(two_widths + ": <size> has two <width>"),
            std::string::npos) << messageOf([&] { readVocLabels(two_widths, &declared); });
  const std::string two_sizes = writeTemp("two_sizes.xml", "<annotation><size><width>160</width><height>120</height>"
                                                           "</size><size><width>1920</width><height>1200</height>"
                                                           "</size>" + object + "</annotation>");
  EXPECT_NE(messageOf([&] { readVocLabels(two_sizes, &declared); }).find(two_sizes + " has two <size>"),
            std::string::npos) << messageOf([&] { readVocLabels(two_sizes, &declared); });

  LabelledFrame f;
  f.name = "frame_9.jpg";
  f.image = cv::Mat(120, 160, CV_8UC3, cv::Scalar::all(90));
  f.labels = {{"red", cv::Rect(10, 5, 20, 20)}, {"green", cv::Rect(50, 5, 20, 20)}};
  f.declared_size = cv::Size(1920, 1200);
  const std::string m = messageOf([&] { checkLabels({f}, options()); });
  EXPECT_NE(m.find("frame_9.jpg: its annotation declares a 1920x1200 image, the image is 160x120"), std::string::npos) << m;
  f.declared_size = cv::Size(160, 120);
  EXPECT_NO_THROW(checkLabels({f}, options()));
}

TEST(ColourLearning, ChoosesPerColourThresholdsWithinTheFalseBudget) {
  LearningOptions o = options();
  LabelledFrame f;
  f.name = "hand-made";
  f.labels = {{"buoy_red", cv::Rect(0, 0, 40, 40)}, {"buoy_green", cv::Rect(100, 0, 40, 40)}};
  auto detection = [](const char* colour, cv::Rect roi, double confidence) {
    Detection d;
    d.colour = colour;
    d.roi = roi;
    d.confidence = confidence;
    return d;
  };
  const std::vector<std::vector<Detection>> detections{{detection("red", {10, 10, 20, 20}, 0.6),
                                                        detection("red", {200, 200, 20, 20}, 0.4),
                                                        detection("green", {110, 10, 20, 20}, 0.45),
                                                        detection("green", {300, 200, 20, 20}, 0.32)}};
  const std::vector<double> grid{0.3, 0.4, 0.5};
  // No false detection allowed: red needs 0.5 (its false one has 0.4), green 0.4 (its false one 0.32).
  const ThresholdChoice none = chooseThresholds({f}, detections, o, grid, 0.0);
  EXPECT_EQ(none.min_confidence, (std::vector<double>{0.5, 0.4}));
  EXPECT_EQ(none.score.found, (std::vector<int>{1, 1}));
  EXPECT_EQ(none.score.false_detections, 0);
  // Scored alike by scoreDetections, with the false ones per colour.
  const LearningScore low = scoreDetections({f}, detections, o, {0.3, 0.3});
  EXPECT_EQ(low.false_detections, 2);
  EXPECT_EQ(low.false_by_colour, (std::vector<int>{1, 1}));
  // A green found only at 0.3 with its false one: within a budget of one false, recall wins.
  std::vector<std::vector<Detection>> weak = detections;
  weak[0][2].confidence = 0.35;
  const ThresholdChoice one = chooseThresholds({f}, weak, o, grid, 1.0);
  EXPECT_EQ(one.min_confidence, (std::vector<double>{0.5, 0.3}));
  EXPECT_EQ(one.score.false_detections, 1);
  // Nothing within the budget: the fewest false.
  const ThresholdChoice fewest = chooseThresholds({f}, weak, o, {0.3}, 0.0);
  EXPECT_EQ(fewest.score.false_detections, 2);
  EXPECT_THROW(scoreDetections({f}, detections, o, {0.3}), std::invalid_argument) << "one threshold for two colours";
}

TEST(ColourLearning, PerColourThresholdsActLikeTheDetectorSetToThem) {
  std::vector<LabelledFrame> train, test;
  for (unsigned s = 0; s < 20; ++s) train.push_back(syntheticFrame(s));
  for (unsigned s = 3000; s < 3015; ++s) test.push_back(syntheticFrame(s));
  const LearningOptions o = options();
  const auto model = std::make_shared<const ColourModel>(learnt(train, o));
  DetectorConfig c = learnedConfig(baseConfig(), "in memory", model, o);
  c.learned.min_confidence = 0.2;
  const auto detections = detectionsOf(Detector(c), test);
  const std::vector<double> per_colour{0.7, 0.3};
  c.colours.classes[0].min_confidence = per_colour[0];
  c.colours.classes[1].min_confidence = per_colour[1];
  const LearningScore alone = score(Detector(c), test, o);
  const LearningScore filtered = scoreDetections(test, detections, o, per_colour);
  EXPECT_EQ(filtered.found, alone.found);
  EXPECT_EQ(filtered.false_detections, alone.false_detections);
  EXPECT_EQ(filtered.false_by_colour, alone.false_by_colour);
}

TEST(ColourLearning, AModelOfEarlierFeaturesReadsTheirColumns) {
  // config/detector.yaml's model was learnt with the first 30 features; today's proposals have more.
  const DetectorConfig c = loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml");
  ASSERT_TRUE(c.learned.model);
  cv::Mat features = cv::Mat::zeros(3, kBlobFeatureCount, CV_32F);
  EXPECT_EQ(c.learned.model->classify(features).size(), 3u);
  EXPECT_THROW(c.learned.model->classify(cv::Mat::zeros(3, 30, CV_32F)), std::invalid_argument)
      << "rows of the wrong width";
}

// config/detector.yaml says its values are the defaults: its colour_model settings are the core's, so a config
// that leaves a key out gets what the file shows.
TEST(ColourLearning, TheDefaultConfigFileHoldsTheCoresDefaults) {
  const LearnedColourConfig file = loadDetectorConfigFile(UWS_SOURCE_DIR "/config/detector.yaml").learned;
  const LearnedColourConfig core;
  EXPECT_DOUBLE_EQ(file.min_confidence, core.min_confidence);
  EXPECT_DOUBLE_EQ(file.max_overlap, core.max_overlap);
  EXPECT_DOUBLE_EQ(file.water.background_scale, core.water.background_scale);
  EXPECT_DOUBLE_EQ(file.water.object_level, core.water.object_level);
  EXPECT_EQ(file.proposals.levels, core.proposals.levels);
  EXPECT_EQ(file.proposals.max_proposals, core.proposals.max_proposals);
  EXPECT_DOUBLE_EQ(file.proposals.piece_step, core.proposals.piece_step);
  EXPECT_DOUBLE_EQ(file.check_min_confidence, core.check_min_confidence);
  EXPECT_DOUBLE_EQ(file.check_from_confidence, core.check_from_confidence);
  EXPECT_DOUBLE_EQ(file.check_rename_margin, core.check_rename_margin);
}

TEST(ColourLearning, ZoomedCopiesKeepTheirLabelsOnTheirObjects) {
  const LearningOptions o = options();
  for (unsigned seed = 0; seed < 10; ++seed) {
    const LabelledFrame f = syntheticFrame(seed);
    const LabelledFrame z = zoomedIn(f, seed, o);
    SCOPED_TRACE(f.name);
    ASSERT_EQ(z.image.size(), f.image.size());
    ASSERT_FALSE(z.labels.empty()) << "cut around a labelled object";
    for (const LabelBox& l : z.labels) {
      EXPECT_EQ(l.box & cv::Rect(cv::Point(), z.image.size()), l.box) << "clipped to the image";
      // A buoy's centre pixel keeps its colour (the synthetic buoys are discs filling their boxes).
      const cv::Point c(l.box.x + l.box.width / 2, l.box.y + l.box.height / 2);
      if (l.box.width < 10 || l.box.height < 10 || l.box.width != l.box.height) continue;  // cut by the border
      const cv::Vec3b p = z.image.at<cv::Vec3b>(c);
      if (l.name == "buoy_red") {
        EXPECT_GT(p[2], p[1]) << "red at the red label's centre";
      }
      if (l.name == "buoy_green") {
        EXPECT_GT(p[1], p[2]) << "green at the green label's centre";
      }
    }
  }
}
