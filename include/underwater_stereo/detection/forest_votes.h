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

#include <string>
#include <utility>
#include <vector>

namespace underwater_stereo {

/// Checks the trees stored by cv::ml::RTrees::write or cv::ml::Boost::write at `stored` (the node of a model file)
/// before OpenCV reads them: OpenCV checks a split's feature index only against one past the last one and then reads
/// out of bounds with it, so a corrupt index crashed the reader. `what` names the file and `kind` the trees
/// ("forest") in the message.
/// @throw std::invalid_argument naming the tree and node when the sizes and types are not those of `feature_count`
/// ordered features and a class, or a split names a feature outside [0, feature_count) or a category.
void checkStoredTrees(const cv::FileNode& stored, int feature_count, const std::string& what, const std::string& kind);

/// The forest stored by cv::ml::RTrees::write at `forest`, read by OpenCV once checkStoredTrees passed it.
cv::Ptr<cv::ml::RTrees> readStoredForest(const cv::FileNode& forest, int feature_count, const std::string& what);

/// Checks that every split of `trees` (a forest or boosted trees, read from a file) names a split and one of
/// `feature_count` features, and links forward to nodes inside the trees, so that every walk ends inside them.
/// @throw std::invalid_argument naming the node that does not.
void checkTreeLinks(const cv::ml::DTrees& trees, int feature_count);

class ForestVotes {
 public:
  ForestVotes() = default;
  /// Copies `forest` (a trained classifier over `feature_count` ordered features).
  /// @throw std::invalid_argument when it is not one, or its copy votes other than getVotes on probe samples
  /// (a split on a categorical feature, which our models never have, would be one).
  ForestVotes(const cv::ml::RTrees& forest, int feature_count);

  bool empty() const { return roots_.empty(); }
  int trees() const { return static_cast<int>(roots_.size()); }
  /// The class label of each vote count, in getVotes' order (its row 0).
  const std::vector<int>& labels() const { return labels_; }
  /// The votes of every tree for `sample` (the forest's features), one count per label into `counts`
  /// (labels().size() ints, overwritten).
  void vote(const float* sample, int* counts) const;

  /// Of vote() `counts`, the label with the most votes among those `eligible(label)` accepts (the first on a
  /// tie), and its share of all the votes; {-1, 0} when none of them got a vote.
  template <typename Eligible>
  std::pair<int, double> best(const int* counts, Eligible eligible) const {
    int total = 0, most = 0, label = -1;
    for (std::size_t j = 0; j < labels_.size(); ++j) {
      total += counts[j];
      if (counts[j] > most && eligible(labels_[j])) {
        most = counts[j];
        label = labels_[j];
      }
    }
    return {label, total > 0 ? double(most) / total : 0.0};
  }

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
};

}  // namespace underwater_stereo
