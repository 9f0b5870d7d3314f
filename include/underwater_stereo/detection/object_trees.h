// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Boosted trees that decide whether a region is an object of some designated colour or background (OpenCV's
/// cv::ml::Boost, gentle AdaBoost): the check's decision after stereo (detection_check.h), and a colour model's
/// decision where it is learnt with them (learn_colours --boosted-trees). A forest still names the colour: boosting
/// is a two-class learner, and the forest's per-colour votes name colours as well as ever. Chosen over the forest's
/// own votes for the decision by learning both from the same data and judging them on data neither saw: more objects
/// at every rate of false detections, after stereo (docs/accuracy.md, "The check decides by boosted trees") and on
/// the real pool frames (docs/accuracy.md, "Real pool images": cross-validated).

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include <string>
#include <vector>

namespace underwater_stereo {

/// How the boosted trees are learnt.
struct BoostedTraining {
  int trees = 400;
  int depth = 6;  ///< OpenCV's other defaults: trimming at 0.95, 10 samples a split

  std::vector<std::string> validate() const;
};

class ObjectTrees {
 public:
  ObjectTrees() = default;
  /// Learns object (a label >= 0) against background (-1) from `samples` (CV_32F, one row per label, both kinds
  /// present: the caller checks), OpenCV's random generator seeded with `seed`.
  /// @throw std::invalid_argument on bad options.
  static ObjectTrees train(const cv::Mat& samples, const std::vector<int>& labels, const BoostedTraining& options,
                           int seed);
  /// The trees stored at `stored` (written by write()) over `width` features; `named` names the file in errors.
  /// @throw std::invalid_argument naming the file, the tree and the node when they are no sound gentle AdaBoost
  /// classifier of `width` ordered features (a split outside them, a link out of the trees, a vote outside [-1, 1]).
  static ObjectTrees read(const cv::FileNode& stored, int width, const std::string& named);
  void write(cv::FileStorage& fs) const;

  bool empty() const { return trees_.empty(); }
  /// How sure they are that `row` (`width` features) is an object, 0-1, above 0.5 an object: one half plus half the
  /// trees' mean vote (gentle AdaBoost's trees vote within [-1, 1]).
  double score(const float* row) const;

 private:
  cv::Ptr<cv::ml::Boost> trees_;
  int width_ = 0;
};

}  // namespace underwater_stereo
