// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/colour_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/blob_proposals.h"

namespace underwater_stereo {
namespace {

/// The forest's class label of background; colour k is k + 1.
constexpr int kBackground = 0;

}  // namespace

std::vector<std::string> ColourModelTraining::validate() const {
  std::vector<std::string> p = ForestTraining::validate();
  if (boosted.trees != 0) {
    for (std::string& b : boosted.validate()) p.push_back(b + " (or 0: none)");
  }
  return p;
}

std::vector<int> countColourLabels(const cv::Mat& samples, const std::vector<int>& labels,
                                   const std::vector<std::string>& colours, const std::vector<std::string>& features,
                                   const std::string& who) {
  const int width = static_cast<int>(features.size());
  if (samples.type() != CV_32FC1 || width == 0 || samples.cols != width || samples.rows != static_cast<int>(labels.size())) {
    throw std::invalid_argument(who + ": need one CV_32F row of " + std::to_string(width) + " features per label");
  }
  if (colours.empty()) throw std::invalid_argument(who + ": no colours to learn");
  std::vector<int> counts(colours.size() + 1, 0);
  for (int l : labels) {
    if (l < -1 || l >= static_cast<int>(colours.size())) throw std::invalid_argument(who + ": label out of range");
    ++counts[static_cast<std::size_t>(l + 1)];
  }
  if (counts[kBackground] == 0) throw std::invalid_argument(who + ": no background samples");
  for (std::size_t k = 0; k < colours.size(); ++k) {
    if (counts[k + 1] == 0) throw std::invalid_argument(who + ": no samples of colour '" + colours[k] + "'");
  }
  return counts;
}

ColourModel ColourModel::train(const cv::Mat& samples, const std::vector<int>& labels,
                               const std::vector<std::string>& colours, const ColourModelTraining& options,
                               const std::vector<std::string>& features) {
  const auto problems = options.validate();
  if (!problems.empty()) throw std::invalid_argument("ColourModel::train: " + problems.front());
  const std::vector<int> counts = countColourLabels(samples, labels, colours, features, "ColourModel::train");
  const int width = static_cast<int>(features.size());
  cv::Mat responses(samples.rows, 1, CV_32SC1);
  for (int i = 0; i < samples.rows; ++i) responses.at<int>(i) = labels[static_cast<std::size_t>(i)] + 1;
  cv::Mat priors(1, static_cast<int>(counts.size()), CV_32F);
  for (std::size_t k = 0; k < counts.size(); ++k) {
    priors.at<float>(static_cast<int>(k)) =
        static_cast<float>(std::pow(double(counts[kBackground]) / counts[k], options.balance));
  }
  ColourModel m;
  m.colours_ = colours;
  m.features_ = features;
  m.feature_count_ = width;
  m.forest_ = trainForest(samples, responses, priors, options);
  m.votes_ = ForestVotes(*m.forest_, m.feature_count_);
  if (options.boosted.trees > 0) m.object_ = ObjectTrees::train(samples, labels, options.boosted, options.seed);
  return m;
}

ColourModel ColourModel::withObjectTrees(const cv::Mat& samples, const std::vector<int>& labels,
                                         const BoostedTraining& options, int seed) const {
  if (empty()) throw std::invalid_argument("ColourModel::withObjectTrees: empty model");
  countColourLabels(samples, labels, colours_, features_, "ColourModel::withObjectTrees");
  ColourModel m = *this;
  m.object_ = ObjectTrees::train(samples, labels, options, seed);
  return m;
}

ColourModel ColourModel::load(const std::string& path, const std::vector<std::string>& names, const std::string& what) {
  const std::string named = what + " " + path;
  const cv::FileStorage fs = openModelFile(path, named);
  return read(fs, names, named);
}

ColourModel ColourModel::read(const cv::FileStorage& fs, const std::vector<std::string>& names, const std::string& named) {
  ColourModel m;
  m.features_ = names;
  std::vector<std::string> features;
  try {
    fs["colours"] >> m.colours_;
    fs["features"] >> features;
    // A model of an earlier build reads the first of today's features (new ones are only ever appended).
    if (features.empty() || features.size() > names.size() || !std::equal(features.begin(), features.end(), names.begin())) {
      throw std::invalid_argument(named + ": made for other features (" + std::to_string(features.size()) +
                                  " named; this build computes " + std::to_string(names.size()) + "): learn it again");
    }
    m.feature_count_ = static_cast<int>(features.size());
    if (m.colours_.empty()) throw std::invalid_argument(named + ": names no colours");
    m.forest_ = readStoredForest(fs["forest"], m.feature_count_, named + ": ");
    // The boosted trees read every feature of this build (a forest of an earlier build may read fewer).
    if (!fs["object"].empty()) m.object_ = ObjectTrees::read(fs["object"], static_cast<int>(names.size()), named);
  } catch (const cv::Exception& e) {
    throw std::invalid_argument(named + ": invalid (" + e.msg + ")");
  }
  try {  // also refuses a forest that is no trained classifier of feature_count_ features
    m.votes_ = ForestVotes(*m.forest_, m.feature_count_);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(named + ": " + e.what());
  }
  return m;
}

void ColourModel::save(const std::string& path, const std::string& what) const {
  if (empty()) throw std::runtime_error("ColourModel::save: empty model");
  cv::FileStorage fs = createModelFile(path, what + " " + path);
  write(fs);
}

void ColourModel::write(cv::FileStorage& fs) const {
  if (empty()) throw std::runtime_error("ColourModel::write: empty model");
  fs << "colours" << colours_;
  fs << "features" << std::vector<std::string>(features_.begin(), features_.begin() + feature_count_);
  fs << "forest" << "{";
  forest_->write(fs);
  fs << "}";
  if (!object_.empty()) {
    fs << "object" << "{";
    object_.write(fs);
    fs << "}";
  }
}

double ColourModel::objectScore(const float* row) const {
  if (object_.empty()) throw std::invalid_argument("ColourModel::objectScore: no boosted trees");
  return object_.score(row);
}

std::vector<ColourVerdict> ColourModel::classify(const cv::Mat& features) const {
  if (empty()) throw std::invalid_argument("ColourModel::classify: empty model");
  if (features.empty()) return {};
  if (features.type() != CV_32FC1 || features.cols != static_cast<int>(features_.size())) {
    throw std::invalid_argument("ColourModel::classify: need CV_32F rows of " + std::to_string(features_.size()) +
                                " features, got " + std::to_string(features.cols) + " columns");
  }
  // The best colour is reported with its share (or the boosted trees' score) even when background has more votes: the
  // caller's threshold (colour_model.min_confidence) decides.
  std::vector<int> counts(votes_.labels().size());
  std::vector<ColourVerdict> verdicts(features.rows);
  for (int i = 0; i < features.rows; ++i) {
    votes_.vote(features.ptr<float>(i), counts.data());
    const auto [label, share] = votes_.best(counts.data(), [](int l) { return l != kBackground; });
    verdicts[i].colour = label < 0 ? -1 : label - 1;
    verdicts[i].share = share;
    verdicts[i].confidence = !object_.empty() && label >= 0 ? object_.score(features.ptr<float>(i)) : share;
    int total = 0;
    for (int n : counts) total += n;
    verdicts[i].shares.assign(colours_.size() + 1, 0.f);
    for (std::size_t j = 0; j < counts.size(); ++j) {
      const int l = votes_.labels()[j];  // kBackground, or colour l - 1
      if (l >= 0 && l <= static_cast<int>(colours_.size()) && total > 0) verdicts[i].shares[l] = float(counts[j]) / total;
    }
  }
  return verdicts;
}

}  // namespace underwater_stereo
