// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A trained random forest (cv::ml::RTrees classifier) copied into flat arrays for voting.
///
/// OpenCV's getVotes walks each tree in a separate call per sample (buffers set up, flags decoded, every call):
/// for the colour model's ~300 proposals of a frame x 100 trees that was 4.5 ms of a 1920x1200 pair's 2D stage,
/// ten times the walks themselves. The trees are copied once, at load, and walked with OpenCV's own rule for an
/// ordered split (value <= threshold goes left), so every vote is OpenCV's: the copy is checked against getVotes
/// when it is made. (OpenCV's missing-value marker, FLT_MAX, is never a feature of ours; here it is a value.)

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include <vector>

namespace underwater_stereo {

class ForestVotes {
 public:
  ForestVotes() = default;
  /// Copies `forest` (a trained classifier over `feature_count` ordered features).
  /// @throw std::invalid_argument when it is not one, or its copy votes other than getVotes on probe samples
  /// (a split on a categorical feature, which our models never have, would be one).
  ForestVotes(const cv::ml::RTrees& forest, int feature_count);

  bool empty() const { return roots_.empty(); }
  int featureCount() const { return feature_count_; }
  int trees() const { return static_cast<int>(roots_.size()); }
  /// The class label of each vote count, in getVotes' order (its row 0).
  const std::vector<int>& labels() const { return labels_; }
  /// The votes of every tree for `sample` (featureCount() floats), one count per label into `counts`
  /// (labels().size() ints, overwritten).
  void vote(const float* sample, int* counts) const;

 private:
  struct Node {
    int feature = -1;    ///< -1: a leaf
    float threshold = 0;
    int left = -1, right = -1;
    int label_index = 0;        ///< a leaf's vote
  };
  std::vector<Node> nodes_;
  std::vector<int> roots_;
  std::vector<int> labels_;
  int feature_count_ = 0;
};

}  // namespace underwater_stereo
