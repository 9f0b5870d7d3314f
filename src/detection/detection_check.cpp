// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/detection_check.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "underwater_stereo/detection/blob_proposals.h"
#include "underwater_stereo/detection/forest_votes.h"

namespace underwater_stereo {
namespace {

/// Sizes under a millimetre are taken as one (the logarithm stays finite).
constexpr double kLeastSizeM = 1e-3;

/// The boosted trees' class of an object (background: 0).
constexpr int kObject = 1;

}  // namespace

std::vector<std::string> checkFeatureNames(const std::vector<std::string>& colours) {
  std::vector<std::string> names = blobFeatureNames();
  names.push_back("share_background");
  for (const std::string& c : colours) names.push_back("share_" + c);
  for (const char* n : {"range_m", "log_largest_size", "log_smallest_size", "shape", "cut_by_border",
                        "fit_rmse_of_range", "matched_share"}) {
    names.emplace_back(n);
  }
  return names;
}

std::vector<float> checkFeatures(const std::vector<float>& colour_features, const MeasuredForCheck& m) {
  if (colour_features.empty()) throw std::invalid_argument("checkFeatures: the candidate has no colour model's features");
  std::vector<float> f = colour_features;
  for (double v : {m.range_m, std::log(std::max(m.largest_size_m, kLeastSizeM)),
                   std::log(std::max(m.smallest_size_m, kLeastSizeM)), double(m.shape), double(m.cut_by_border),
                   m.fit_rmse_m / std::max(m.range_m, 0.1), m.matched_share}) {
    f.push_back(static_cast<float>(v));
  }
  return f;
}

std::vector<std::string> CheckTraining::validate() const {
  std::vector<std::string> p = colours.validate();
  if (boosted_trees < 1 || boosted_trees > 5000) p.push_back("boosted_trees must be in [1, 5000]");
  if (boosted_depth < 1 || boosted_depth > 20) p.push_back("boosted_depth must be in [1, 20]");
  return p;
}

DetectionCheck DetectionCheck::train(const cv::Mat& samples, const std::vector<int>& labels,
                                     const std::vector<std::string>& colours, const CheckTraining& options,
                                     const ColourModel* naming) {
  const auto problems = options.validate();
  if (!problems.empty()) throw std::invalid_argument("DetectionCheck::train: " + problems.front());
  if (naming != nullptr && (naming->empty() || naming->colours() != colours)) {
    throw std::invalid_argument("DetectionCheck::train: the forest that is to name colours names other colours");
  }
  // Mismatched sizes, labels out of range and a class without samples are refused (so both of the boosted trees'
  // classes have some).
  const std::vector<std::string> features = checkFeatureNames(colours);
  countColourLabels(samples, labels, colours, features, "DetectionCheck::train");
  DetectionCheck c;
  c.colours_ = naming != nullptr ? *naming : ColourModel::train(samples, labels, colours, options.colours, features);
  c.width_ = samples.cols;
  cv::Mat responses(samples.rows, 1, CV_32SC1);
  for (int i = 0; i < samples.rows; ++i) responses.at<int>(i) = labels[i] >= 0 ? kObject : 0;
  cv::theRNG().state = static_cast<std::uint64_t>(options.colours.seed);
  c.object_ = cv::ml::Boost::create();
  c.object_->setBoostType(cv::ml::Boost::GENTLE);
  c.object_->setWeakCount(options.boosted_trees);
  c.object_->setMaxDepth(options.boosted_depth);  // OpenCV's other defaults: trimming at 0.95, 10 samples a split
  c.object_->train(cv::ml::TrainData::create(samples, cv::ml::ROW_SAMPLE, responses));
  return c;
}

DetectionCheck DetectionCheck::load(const std::string& path, const std::vector<std::string>& colours) {
  const std::string named = "check model " + path;
  const cv::FileStorage fs = openModelFile(path, named);
  const std::vector<std::string> names = checkFeatureNames(colours);
  DetectionCheck c;
  c.colours_ = ColourModel::read(fs, names, named);
  c.width_ = static_cast<int>(names.size());
  try {
    if (fs["object"].empty()) {
      throw std::invalid_argument(named + ": no boosted trees (object): a check of an earlier build, learn it again");
    }
    checkStoredTrees(fs["object"], c.width_, named + ": ", "boosted trees");
    c.object_ = cv::ml::Boost::create();
    c.object_->read(fs["object"]);
  } catch (const cv::Exception& e) {
    throw std::invalid_argument(named + ": invalid boosted trees (" + e.msg + ")");
  }
  if (!c.object_->isTrained() || !c.object_->isClassifier() || c.object_->getVarCount() != c.width_ ||
      c.object_->getRoots().empty()) {
    throw std::invalid_argument(named + ": the boosted trees are no trained classifier of " + std::to_string(c.width_) +
                                " features");
  }
  try {
    checkTreeLinks(*c.object_, c.width_);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(named + ": boosted trees: " + e.what());
  }
  for (const cv::ml::DTrees::Node& n : c.object_->getNodes()) {  // gentle AdaBoost's votes lie within [-1, 1]
    if (!(std::abs(n.value) <= 1.0)) {
      throw std::invalid_argument(named + ": boosted trees: a node votes " + std::to_string(n.value) + ", outside [-1, 1]");
    }
  }
  return c;
}

void DetectionCheck::save(const std::string& path) const {
  if (empty()) throw std::runtime_error("DetectionCheck::save: empty check");
  cv::FileStorage fs = createModelFile(path, "check model " + path);
  colours_.write(fs);
  fs << "object" << "{";
  object_->write(fs);
  fs << "}";
}

void DetectionCheck::requireFeatures(const std::vector<float>& features, const char* caller) const {
  if (empty()) throw std::invalid_argument(std::string(caller) + ": empty check");
  if (static_cast<int>(features.size()) != width_) {
    throw std::invalid_argument(std::string(caller) + ": " + std::to_string(features.size()) + " features, not " +
                                std::to_string(width_) + " (a candidate no colour model found?)");
  }
}

double DetectionCheck::objectScore(const std::vector<float>& features) const {
  requireFeatures(features, "DetectionCheck::objectScore");
  const cv::Mat row(1, width_, CV_32F, const_cast<float*>(features.data()));
  const double sum = object_->predict(row, cv::noArray(), cv::ml::DTrees::PREDICT_SUM | cv::ml::StatModel::RAW_OUTPUT);
  const double trees = static_cast<double>(object_->getRoots().size());
  return std::clamp(0.5 + 0.5 * sum / trees, 0.0, 1.0);
}

ColourVerdict DetectionCheck::colourVerdict(const std::vector<float>& features) const {
  requireFeatures(features, "DetectionCheck::colourVerdict");
  return colours_.classify(cv::Mat(features, true).reshape(1, 1)).front();
}

}  // namespace underwater_stereo
