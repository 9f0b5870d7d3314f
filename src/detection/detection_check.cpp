// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/detection_check.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/blob_proposals.h"

namespace underwater_stereo {
namespace {

/// Sizes under a millimetre are taken as one (the logarithm stays finite).
constexpr double kLeastSizeM = 1e-3;

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

DetectionCheck DetectionCheck::train(const cv::Mat& samples, const std::vector<int>& labels,
                                     const std::vector<std::string>& colours, const ColourModelTraining& options,
                                     const ColourModel* naming) {
  if (options.boosted.trees < 1) {
    throw std::invalid_argument("DetectionCheck::train: a check needs boosted trees (1 or more)");
  }
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
  c.colours_ = naming != nullptr ? naming->withObjectTrees(samples, labels, options.boosted, options.seed)
                                 : ColourModel::train(samples, labels, colours, options, features);
  c.width_ = samples.cols;
  return c;
}

DetectionCheck DetectionCheck::load(const std::string& path, const std::vector<std::string>& colours) {
  const std::string named = "check model " + path;
  const cv::FileStorage fs = openModelFile(path, named);
  const std::vector<std::string> names = checkFeatureNames(colours);
  DetectionCheck c;
  c.colours_ = ColourModel::read(fs, names, named);
  c.width_ = static_cast<int>(names.size());
  if (!c.colours_.hasObjectTrees()) {
    throw std::invalid_argument(named + ": no boosted trees (object): a check of an earlier build, learn it again");
  }
  return c;
}

void DetectionCheck::save(const std::string& path) const {
  if (empty()) throw std::runtime_error("DetectionCheck::save: empty check");
  colours_.save(path, "check model");
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
  return colours_.objectScore(features.data());
}

ColourVerdict DetectionCheck::colourVerdict(const std::vector<float>& features) const {
  requireFeatures(features, "DetectionCheck::colourVerdict");
  return colours_.classify(cv::Mat(features, true).reshape(1, 1)).front();
}

}  // namespace underwater_stereo
