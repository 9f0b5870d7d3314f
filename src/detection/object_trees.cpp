// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/object_trees.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "underwater_stereo/detection/forest_votes.h"

namespace underwater_stereo {

std::vector<std::string> BoostedTraining::validate() const {
  std::vector<std::string> p;
  if (trees < 1 || trees > 5000) p.push_back("boosted_trees must be in [1, 5000]");
  if (depth < 1 || depth > 20) p.push_back("boosted_depth must be in [1, 20]");
  return p;
}

ObjectTrees ObjectTrees::train(const cv::Mat& samples, const std::vector<int>& labels, const BoostedTraining& options,
                               int seed) {
  const auto problems = options.validate();
  if (!problems.empty()) throw std::invalid_argument("ObjectTrees::train: " + problems.front());
  if (samples.type() != CV_32FC1 || samples.rows != static_cast<int>(labels.size()) || samples.rows == 0) {
    throw std::invalid_argument("ObjectTrees::train: need one CV_32F row per label");
  }
  cv::Mat responses(samples.rows, 1, CV_32SC1);
  for (int i = 0; i < samples.rows; ++i) responses.at<int>(i) = labels[static_cast<std::size_t>(i)] >= 0 ? 1 : 0;
  cv::theRNG().state = static_cast<std::uint64_t>(seed);
  ObjectTrees t;
  t.width_ = samples.cols;
  t.trees_ = cv::ml::Boost::create();
  t.trees_->setBoostType(cv::ml::Boost::GENTLE);
  t.trees_->setWeakCount(options.trees);
  t.trees_->setMaxDepth(options.depth);
  t.trees_->train(cv::ml::TrainData::create(samples, cv::ml::ROW_SAMPLE, responses));
  return t;
}

ObjectTrees ObjectTrees::read(const cv::FileNode& stored, int width, const std::string& named) {
  ObjectTrees t;
  t.width_ = width;
  try {
    checkStoredTrees(stored, width, named + ": ", "boosted trees");
    t.trees_ = cv::ml::Boost::create();
    t.trees_->read(stored);
  } catch (const cv::Exception& e) {
    throw std::invalid_argument(named + ": invalid boosted trees (" + e.msg + ")");
  }
  if (!t.trees_->isTrained() || !t.trees_->isClassifier() || t.trees_->getVarCount() != width ||
      t.trees_->getRoots().empty()) {
    throw std::invalid_argument(named + ": the boosted trees are no trained classifier of " + std::to_string(width) +
                                " features");
  }
  try {
    checkTreeLinks(*t.trees_, width);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(named + ": boosted trees: " + e.what());
  }
  for (const cv::ml::DTrees::Node& n : t.trees_->getNodes()) {  // gentle AdaBoost's votes lie within [-1, 1]
    if (!(std::abs(n.value) <= 1.0)) {
      throw std::invalid_argument(named + ": boosted trees: a node votes " + std::to_string(n.value) + ", outside [-1, 1]");
    }
  }
  return t;
}

void ObjectTrees::write(cv::FileStorage& fs) const {
  if (empty()) throw std::runtime_error("ObjectTrees::write: no trees");
  trees_->write(fs);
}

double ObjectTrees::score(const float* row) const {
  if (empty()) throw std::invalid_argument("ObjectTrees::score: no trees");
  const cv::Mat sample(1, width_, CV_32F, const_cast<float*>(row));
  const double sum = trees_->predict(sample, cv::noArray(), cv::ml::DTrees::PREDICT_SUM | cv::ml::StatModel::RAW_OUTPUT);
  return std::clamp(0.5 + 0.5 * sum / static_cast<double>(trees_->getRoots().size()), 0.0, 1.0);
}

}  // namespace underwater_stereo
