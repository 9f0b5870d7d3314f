// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A learnt model that names a proposed region's colour, or rejects it as background.
///
/// OpenCV's random trees (cv::ml::RTrees) over the features of blob_proposals.h, trained by learn_colours from
/// labelled frames (real footage or the simulator's ground truth), and optionally boosted trees (object_trees.h) that
/// decide object or background in their place while the forest still names the colour. The same kind of model, over
/// the features of detection_check.h, checks each detection again after stereo (learn_checks). Chosen over a hand-made
/// rule set because the features that separate a buoy from the floor, the walls and the water differ from pool to
/// pool; the forest over SVMs because it gives per-class votes (a confidence) in one pass, needs no feature scaling and
/// predicts a few hundred regions per frame in well under a millisecond (docs/accuracy.md: one SVM per colour found
/// fewer real buoys); boosted trees for the decision where they find more at the same false detections.

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include <string>
#include <vector>

#include "underwater_stereo/detection/blob_proposals.h"
#include "underwater_stereo/detection/forest_training.h"
#include "underwater_stereo/detection/forest_votes.h"
#include "underwater_stereo/detection/object_trees.h"

namespace underwater_stereo {

struct ColourVerdict {
  int colour = -1;          ///< index into ColourModel::colours(), -1 = background
  /// How sure the model is of an object of that colour, 0-1: the share of the trees voting for it, or with boosted
  /// trees their object score (ObjectTrees::score; 0.5 where their votes even out).
  double confidence = 0.0;
  /// Share of the trees voting for each class: background first, then ColourModel::colours() in order.
  std::vector<float> shares;
  double share = 0.0;  ///< the share of the forest's trees voting for that colour (0-1)
};

/// Training options of the colour model: its forest (the background is the reference class of `balance`; `seed` seeds
/// the boosted trees too) and its boosted trees, none when `boosted.trees` is 0.
struct ColourModelTraining : ForestTraining {
  BoostedTraining boosted{0, 6};

  std::vector<std::string> validate() const;
};

/// The samples of each class in `labels` (-1: background, k: colours[k]); index 0 of the result counts the
/// background, k + 1 colour k. @throw std::invalid_argument beginning with `who` unless `samples` holds one CV_32F
/// row of `features` per label, every label is -1 or a colour's index, and background and every colour have samples.
std::vector<int> countColourLabels(const cv::Mat& samples, const std::vector<int>& labels,
                                   const std::vector<std::string>& colours, const std::vector<std::string>& features,
                                   const std::string& who);

class ColourModel {
 public:
  ColourModel() = default;
  /// Trains on `samples` (CV_32F, one row of features per region, in the order of `features`: by default a
  /// proposal's, blobFeatureNames()) with `labels` (-1: background, k: colours[k]); the boosted trees too when
  /// `options.boosted.trees` > 0.
  /// @throw std::invalid_argument on mismatched sizes, a colour without any sample, or no background sample.
  static ColourModel train(const cv::Mat& samples, const std::vector<int>& labels, const std::vector<std::string>& colours,
                           const ColourModelTraining& options,
                           const std::vector<std::string>& features = blobFeatureNames());
  /// This model's forest with boosted trees learnt from `samples` and `labels` (as train(), over this model's
  /// features and colours) in place of any it has. @throw std::invalid_argument as train().
  ColourModel withObjectTrees(const cv::Mat& samples, const std::vector<int>& labels, const BoostedTraining& options,
                              int seed) const;
  /// A model of `features` (a model of an earlier build may read only their first ones); `what` names it in errors
  /// ("colour model", "check model").
  /// @throw std::invalid_argument naming the file when it cannot be read or is not a model of these features.
  static ColourModel load(const std::string& path, const std::vector<std::string>& features = blobFeatureNames(),
                          const std::string& what = "colour model");
  /// A model of `features` from the top level of an opened model file (openModelFile); `named` names the file in
  /// errors. @throw std::invalid_argument as load().
  static ColourModel read(const cv::FileStorage& fs, const std::vector<std::string>& features, const std::string& named);
  /// @throw std::runtime_error naming the file (as `what`) when it cannot be written.
  void save(const std::string& path, const std::string& what = "colour model") const;
  /// Writes the model at the top level of `fs` (a file save() or a file holding more than the model).
  void write(cv::FileStorage& fs) const;

  bool empty() const { return forest_.empty(); }
  const std::vector<std::string>& colours() const { return colours_; }
  bool hasObjectTrees() const { return !object_.empty(); }
  /// The boosted trees' object score of `row` (the model's features). @throw std::invalid_argument without them.
  double objectScore(const float* row) const;
  /// For each row of `features` (CV_32F, a column per feature the model was made for: one region), its best
  /// colour (-1 when no tree votes for any colour) and how sure the model is of it (the share of trees voting for it,
  /// or the boosted trees' object score), and every class's share; the forest is walked as ForestVotes.
  /// @throw std::invalid_argument when features has the wrong type or width, or the model is empty.
  std::vector<ColourVerdict> classify(const cv::Mat& features) const;

 private:
  std::vector<std::string> colours_;
  std::vector<std::string> features_;  ///< the features a row holds (train's or load's `features`)
  cv::Ptr<cv::ml::RTrees> forest_;  ///< kept for save()
  ForestVotes votes_;               ///< the same trees, walked by classify()
  ObjectTrees object_;              ///< empty: the forest's votes decide
  int feature_count_ = 0;  ///< it reads the first this many features (a model of an earlier build: fewer)
};

}  // namespace underwater_stereo
