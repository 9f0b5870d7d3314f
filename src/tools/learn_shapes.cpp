// SPDX-License-Identifier: BSD-3-Clause
// learn_shapes: learns the detector's shape model (shape.model_file) from evaluate_detector's JSON records of
// randomised scenes: every eligible object found, with the shape features of its detection and its true shape.
#include <yaml-cpp/yaml.h>

#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "underwater_stereo/detection/shape_features.h"
#include "underwater_stereo/detection/shape_model.h"
#include "tool_helpers.h"

namespace {

using namespace underwater_stereo;

const char* kUsage =
    "usage: learn_shapes --out MODEL.yml.gz RECORDS.json...\n"
    "  RECORDS: evaluate_detector --random N --seed S --json RECORDS (use seeds never used for judging).\n"
    "  Learns from each eligible object found (its detection's shape_features, its true shape) and writes the\n"
    "  model; name it in the detector configuration as shape.model_file.\n";

/// Adds the samples of one records file. @throw std::invalid_argument naming the file on malformed records.
void addRecords(const std::string& path, cv::Mat& samples, std::vector<ShapeKind>& labels) {
  const YAML::Node root = tools::loadRandomRecords(path);
  tools::forEachRecordPair(root, path, [&](const YAML::Node& pair, const std::string& where) {
    for (const YAML::Node& o : pair["objects"]) {
      const bool eligible = tools::recordFlag(o, "eligible"), found = tools::recordFlag(o, "found");  // both checked
      if (!eligible || !found) continue;
      const YAML::Node f = o["detected"]["shape_features"];
      if (!f || !f.IsSequence()) {
        throw std::invalid_argument(where + ": a found object without detected.shape_features (records older than the "
                                            "shape model?)");
      }
      if (f.size() == 0) continue;  // too few points to describe
      if (static_cast<int>(f.size()) != kShapeFeatureCount) {
        throw std::invalid_argument(where + ": " + std::to_string(f.size()) + " shape features per object, this build computes " +
                                    std::to_string(kShapeFeatureCount) + ": evaluate again with this build");
      }
      cv::Mat row(1, kShapeFeatureCount, CV_32F);
      for (int j = 0; j < kShapeFeatureCount; ++j) row.at<float>(j) = tools::recordFeature(f[j]);
      samples.push_back(row);
      labels.push_back(shapeFromName(o["shape"].as<std::string>(), where + ": shape"));
    }
  });
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> values{{"--out", ""}};
  std::vector<std::string> inputs;
  if (const int code = tools::parseRecordsCommandLine(argc, argv, "learn_shapes", kUsage, values, inputs); code >= 0) {
    return code;
  }
  const std::string& out = values["--out"];
  if (out.empty() || inputs.empty()) {
    std::cerr << "learn_shapes: give --out MODEL and at least one records file\n" << kUsage;
    return 2;
  }
  if (const int code = tools::checkOutputAndRecords("learn_shapes", kUsage, out, "the shape model file to write (MODEL.yml.gz)",
                                                    inputs, "its objects would be learnt twice");
      code >= 0) {
    return code;
  }
  try {
    cv::Mat samples(0, kShapeFeatureCount, CV_32F);
    std::vector<ShapeKind> labels;
    for (const std::string& path : inputs) addRecords(path, samples, labels);
    std::map<ShapeKind, int> counts;
    for (ShapeKind s : labels) ++counts[s];
    tools::trainOnRecords(inputs, labels.size(), "objects", [&] {
      return ShapeModel::train(samples, labels, ShapeModelTraining{});
    }).save(out);
    std::cout << "learnt from " << labels.size() << " objects (";
    for (const auto& [shape, n] : counts) std::cout << " " << shape << " " << n;
    std::cout << " ); wrote " << out << "\n";
  } catch (const std::exception& e) {
    std::cerr << "learn_shapes: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
