// SPDX-License-Identifier: BSD-3-Clause
// ForestVotes: the copied trees vote exactly as OpenCV's getVotes.
#include <gtest/gtest.h>

#include <opencv2/ml.hpp>

#include "underwater_stereo/detection/forest_training.h"
#include "underwater_stereo/detection/forest_votes.h"

using namespace underwater_stereo;

namespace {

/// Three overlapping classes over 6 features (labels -1, 0, 2, as the colour model's background and colours).
cv::Ptr<cv::ml::RTrees> trainedForest(cv::Mat& samples) {
  cv::RNG rng(7);
  samples.create(600, 6, CV_32F);
  cv::Mat responses(600, 1, CV_32S);
  const int labels[3] = {-1, 0, 2};
  for (int r = 0; r < samples.rows; ++r) {
    const int k = r % 3;
    for (int f = 0; f < samples.cols; ++f) samples.at<float>(r, f) = static_cast<float>(rng.gaussian(1.0) + (f == k ? 1.5 : 0.0));
    responses.at<int>(r) = labels[k];
  }
  ForestTraining options;
  options.trees = 30;
  options.max_depth = 8;
  return trainForest(samples, responses, cv::Mat::ones(1, 3, CV_32F), options);
}

}  // namespace

TEST(ForestVotes, VotesExactlyAsOpenCVsGetVotes) {
  cv::Mat training;
  const cv::Ptr<cv::ml::RTrees> forest = trainedForest(training);
  const ForestVotes votes(*forest, 6);
  EXPECT_EQ(votes.trees(), 30);
  EXPECT_EQ(votes.labels(), (std::vector<int>{-1, 0, 2}));
  // New samples, some far outside the training range.
  cv::Mat samples(400, 6, CV_32F);
  cv::RNG rng(11);
  rng.fill(samples, cv::RNG::UNIFORM, -6.0, 6.0);
  cv::vconcat(samples, training, samples);
  cv::Mat expected;
  forest->getVotes(samples, expected, 0);
  std::vector<int> counts(3);
  for (int r = 0; r < samples.rows; ++r) {
    votes.vote(samples.ptr<float>(r), counts.data());
    for (int k = 0; k < 3; ++k) ASSERT_EQ(counts[k], expected.at<int>(1 + r, k)) << "sample " << r << ", class " << k;
  }
}

TEST(ForestVotes, RefusesWhatIsNotATrainedClassifierOfThoseFeatures) {
  EXPECT_THROW(ForestVotes(*cv::ml::RTrees::create(), 6), std::invalid_argument);
  cv::Mat training;
  const cv::Ptr<cv::ml::RTrees> forest = trainedForest(training);
  EXPECT_THROW(ForestVotes(*forest, 5), std::invalid_argument);
  EXPECT_TRUE(ForestVotes().empty());
}

// OpenCV's reader accepts a split on the feature one past the last and then reads out of bounds with it (a crash):
// a stored forest is checked first, and a corrupt index is named with its tree and node.
TEST(ForestVotes, AStoredForestSplittingOnAFeatureItHasNotIsRefusedBeforeOpenCVReadsIt) {
  cv::Mat training;
  const cv::Ptr<cv::ml::RTrees> forest = trainedForest(training);
  cv::FileStorage out(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  out << "forest" << "{";
  forest->write(out);
  out << "}";
  const std::string text = out.releaseAndGetString();
  auto stored = [](const std::string& yaml) { return cv::FileStorage(yaml, cv::FileStorage::READ | cv::FileStorage::MEMORY); };
  EXPECT_NO_THROW(readStoredForest(stored(text)["forest"], 6, "m.yml: "));
  EXPECT_THROW(readStoredForest(stored(text)["forest"], 5, "m.yml: "), std::invalid_argument);
  for (const char* bad : {"var:6", "var:7", "var:-1"}) {
    std::string corrupt = text;
    const std::size_t at = corrupt.find("var:");
    ASSERT_NE(at, std::string::npos);
    corrupt.replace(at, corrupt.find(',', at) - at, bad);
    try {
      readStoredForest(stored(corrupt)["forest"], 6, "m.yml: ");
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("m.yml: forest: tree 0 node 0 splits on feature"), std::string::npos) << e.what();
    }
  }
  // A feature made categorical, and a split on a category (OpenCV writes out of bounds reading its subset).
  std::string categorical = text;
  const std::string first_type = "var_type: [ 0";
  const std::size_t types = categorical.find(first_type);
  ASSERT_NE(types, std::string::npos) << text.substr(0, 600);
  categorical.replace(types, first_type.size(), "var_type: [ 1");
  EXPECT_THROW(readStoredForest(stored(categorical)["forest"], 6, "m.yml: "), std::invalid_argument);
  std::string category = text;
  const std::size_t var = category.find("var:");
  category.insert(var, "in:[ 0 ], ");
  EXPECT_THROW(readStoredForest(stored(category)["forest"], 6, "m.yml: "), std::invalid_argument);
}
