// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A learnt model that names a proposed region's colour, or rejects it as background.
///
/// OpenCV's random trees (cv::ml::RTrees) over the features of blob_proposals.h, trained by learn_colours from
/// labelled frames (real footage or the simulator's ground truth). The same kind of model, over the features of
/// detection_check.h, checks each detection again after stereo (learn_checks). Chosen over a hand-made rule set because
/// the features that separate a buoy from the floor, the walls and the water differ from pool to pool; over
/// boosting and SVMs because a forest gives per-class votes (a confidence) in one pass, needs no feature
/// scaling and predicts a few hundred regions per frame in well under a millisecond.

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include <string>
#include <vector>

#include "underwater_stereo/detection/blob_proposals.h"
#include "underwater_stereo/detection/forest_training.h"
#include "underwater_stereo/detection/forest_votes.h"

namespace underwater_stereo {

struct ColourVerdict {
  int colour = -1;          ///< index into ColourModel::colours(), -1 = background
  double confidence = 0.0;  ///< share of the trees voting for the best colour (0-1)
  /// Share of the trees voting for each class: background first, then ColourModel::colours() in order.
  std::vector<float> shares;
};

/// Training options of the colour model (the background is the reference class of `balance`).
using ColourModelTraining = ForestTraining;

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
  /// proposal's, blobFeatureNames()) with `labels` (-1: background, k: colours[k]).
  /// @throw std::invalid_argument on mismatched sizes, a colour without any sample, or no background sample.
  static ColourModel train(const cv::Mat& samples, const std::vector<int>& labels, const std::vector<std::string>& colours,
                           const ColourModelTraining& options,
                           const std::vector<std::string>& features = blobFeatureNames());
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
  /// For each row of `features` (CV_32F, a column per feature the model was made for: one region), its best
  /// colour and the share of trees voting for it (-1 when no tree votes for any colour), and every class's share;
  /// the trees are walked as ForestVotes.
  /// @throw std::invalid_argument when features has the wrong type or width, or the model is empty.
  std::vector<ColourVerdict> classify(const cv::Mat& features) const;

 private:
  std::vector<std::string> colours_;
  std::vector<std::string> features_;  ///< the features a row holds (train's or load's `features`)
  cv::Ptr<cv::ml::RTrees> forest_;  ///< kept for save()
  ForestVotes votes_;               ///< the same trees, walked by classify()
  int feature_count_ = 0;  ///< it reads the first this many features (a model of an earlier build: fewer)
};

}  // namespace underwater_stereo
