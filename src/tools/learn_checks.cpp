// SPDX-License-Identifier: BSD-3-Clause
// learn_checks: learns the detector's check after stereo (colour_model.check_file, detection_check.h) from
// evaluate_detector's JSON records of randomised scenes made with --without-check: every detection the colour
// model passed, with its check features, labelled as the evaluation counts it.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "underwater_stereo/detection/detection_check.h"
#include "underwater_stereo/detection/detector_config.h"
#include "tool_helpers.h"

namespace {

using namespace underwater_stereo;

const char* kUsage =
    "usage: learn_checks --config DETECTOR.yaml --out CHECK.yml.gz [--colours-from CHECK.yml.gz] RECORDS.json...\n"
    "  RECORDS: evaluate_detector --config DETECTOR.yaml --random N --seed S --without-check --json RECORDS\n"
    "  (seeds never used for judging). DETECTOR.yaml names the colour model the records were made with.\n"
    "  Learns from each detection: the first one on an object of a designated colour (0.5-5 m, >= 400 px) as\n"
    "  that colour; one on a distractor, on the background, or a second one on an object as background; one on\n"
    "  an object too small, near or far not at all. Name the model in the configuration as\n"
    "  colour_model.check_file. Boosted trees decide object or background; a forest names colours, learnt from\n"
    "  the same detections or, with --colours-from, the forest of that check file (a check of an earlier build\n"
    "  too) kept as it is.\n";

constexpr int kBackground = -1;

/// What the records' detections teach.
struct Samples {
  cv::Mat rows;
  std::vector<int> labels;  ///< kBackground or a colour's index
};

std::vector<float> featuresOf(const YAML::Node& list, std::size_t width, const std::string& where) {
  if (!list || !list.IsSequence()) {
    throw std::invalid_argument(where + ": no check_features (records older than the check, or not --random records)");
  }
  std::vector<float> f;
  for (const YAML::Node& v : list) f.push_back(tools::recordFeature(v));
  if (!f.empty() && f.size() != width) {
    throw std::invalid_argument(where + ": " + std::to_string(f.size()) + " check features, the configuration's colour "
                                "model gives " + std::to_string(width) + ": make the records with this configuration");
  }
  return f;
}

void addSample(const std::vector<float>& features, int label, Samples& out) {
  if (features.empty()) return;  // not found by a colour model
  out.rows.push_back(cv::Mat(features, true).reshape(1, 1));
  out.labels.push_back(label);
}

/// Adds the samples of one pair's records (`where` names it).
void addPair(const YAML::Node& pair, const std::vector<std::string>& colours, std::size_t width, const std::string& where,
             Samples& out) {
  std::map<std::string, YAML::Node> objects;
  for (const YAML::Node& o : pair["objects"]) {
    objects[o["name"].as<std::string>()] = o;
    const bool found = tools::recordFlag(o, "found"), designated = tools::recordFlag(o, "designated"),
               eligible = tools::recordFlag(o, "eligible");  // all three checked, whatever the first says
    if (!found || !designated || !eligible) continue;
    const auto colour = std::find(colours.begin(), colours.end(), o["colour"].as<std::string>());
    if (colour == colours.end()) continue;  // a designated colour the colour model does not name
    addSample(featuresOf(o["detected"]["check_features"], width, where), static_cast<int>(colour - colours.begin()), out);
  }
  for (const YAML::Node& d : pair["false_detections"]) {
    const std::string on = d["on"].as<std::string>("");
    const auto it = objects.find(on);
    if (!on.empty() && it == objects.end()) throw std::invalid_argument(where + ": a detection on unknown object " + on);
    const bool ineligible_target =
        it != objects.end() && tools::recordFlag(it->second, "designated") &&
        !tools::recordFlag(it->second, "eligible");
    if (ineligible_target) continue;  // neither a target nor a false one
    addSample(featuresOf(d["check_features"], width, where), kBackground, out);
  }
}

/// Adds the samples of one records file. @throw std::invalid_argument naming the file on malformed records.
void addRecords(const std::string& path, const std::string& config_path, const std::vector<std::string>& colours,
                std::size_t width, Samples& out) {
  const YAML::Node root = tools::loadRandomRecords(path);
  if (root["config"] && root["config"].as<std::string>().find("--without-check") == std::string::npos) {
    throw std::invalid_argument(path + ": made with a check (evaluate_detector without --without-check): its records "
                                "lack what the check turned down");
  }
  if (root["config"]) {  // the configuration the records were made with: its colour model gave their features
    const std::string command = root["config"].as<std::string>();
    const std::string made_with = command.substr(0, command.find(" --"));
    std::error_code error;
    if (made_with != config_path && !std::filesystem::equivalent(made_with, config_path, error)) {
      std::cerr << "learn_checks: note: " << path << " was made with " << made_with << ", not " << config_path
                << " (or that path does not lead to it from here): learn from records of the colour model the check "
                << "is for\n";
    }
  }
  tools::forEachRecordPair(root, path, [&](const YAML::Node& pair, const std::string& where) {
    addPair(pair, colours, width, where, out);
  });
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> values{{"--config", ""}, {"--out", ""}, {"--colours-from", ""}};
  std::vector<std::string> inputs;
  if (const int code = tools::parseRecordsCommandLine(argc, argv, "learn_checks", kUsage, values, inputs); code >= 0) {
    return code;
  }
  const std::string& config_path = values["--config"];
  const std::string& out = values["--out"];
  if (out.empty() || config_path.empty() || inputs.empty()) {
    std::cerr << "learn_checks: give --config, --out and at least one records file\n" << kUsage;
    return 2;
  }
  if (const int code = tools::checkOutputAndRecords("learn_checks", kUsage, out, "the check model file to write (CHECK.yml.gz)",
                                                    inputs, "its detections would be learnt twice");
      code >= 0) {
    return code;
  }
  DetectorConfig config;
  std::optional<ColourModel> naming;
  try {  // what the command line names: a bad one exits 2 as a bad option does
    config = loadDetectorConfigFile(config_path, [](YAML::Node& root) {
      if (root.IsMap() && root["colour_model"] && root["colour_model"].IsMap()) root["colour_model"].remove("check_file");
    });
    if (!config.learned.model) throw std::invalid_argument(config_path + ": no colour_model.file: nothing to check");
    if (!values["--colours-from"].empty()) {
      naming = ColourModel::load(values["--colours-from"], checkFeatureNames(config.learned.model->colours()),
                                 "check model");
    }
  } catch (const std::exception& e) {
    std::cerr << "learn_checks: " << e.what() << "\n";
    return 2;
  }
  try {
    const std::vector<std::string>& colours = config.learned.model->colours();
    const std::vector<std::string> names = checkFeatureNames(colours);
    Samples samples;
    samples.rows = cv::Mat(0, static_cast<int>(names.size()), CV_32F);
    for (const std::string& path : inputs) addRecords(path, config_path, colours, names.size(), samples);
    // checkTraining()'s settings: chosen on the records of seeds 86000-87999 and validation seeds 60000-60299.
    tools::trainOnRecords(inputs, samples.labels.size(), "detections", [&] {
      return DetectionCheck::train(samples.rows, samples.labels, colours, checkTraining(), naming ? &*naming : nullptr);
    }).save(out);
    std::map<int, int> counts;
    for (int l : samples.labels) ++counts[l];
    std::cout << "learnt from " << samples.labels.size() << " detections (background " << counts[kBackground];
    for (std::size_t k = 0; k < colours.size(); ++k) std::cout << ", " << colours[k] << " " << counts[int(k)];
    std::cout << "); wrote " << out << "\n";
  } catch (const std::exception& e) {
    std::cerr << "learn_checks: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
