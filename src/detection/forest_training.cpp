// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/forest_training.h"

#include <cstdint>

namespace underwater_stereo {

std::vector<std::string> ForestTraining::validate() const {
  std::vector<std::string> p;
  if (trees < 1 || trees > 2000) p.push_back("trees must be in [1, 2000]");
  if (max_depth < 1 || max_depth > 30) p.push_back("max_depth must be in [1, 30]");
  if (!(balance >= 0 && balance <= 1)) p.push_back("balance must be in [0, 1]");
  return p;
}

cv::Ptr<cv::ml::RTrees> trainForest(const cv::Mat& samples, const cv::Mat& responses, const cv::Mat& priors,
                                    const ForestTraining& options) {
  cv::theRNG().state = static_cast<std::uint64_t>(options.seed);
  cv::Ptr<cv::ml::RTrees> forest = cv::ml::RTrees::create();
  forest->setMaxDepth(options.max_depth);
  forest->setMinSampleCount(2);
  forest->setPriors(priors);
  forest->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER, options.trees, 0));
  forest->train(cv::ml::TrainData::create(samples, cv::ml::ROW_SAMPLE, responses));
  return forest;
}

}  // namespace underwater_stereo
