// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A learnt model that names an object's shape from its outline, 3D points and shading (shape_features.h).
///
/// OpenCV's random trees (cv::ml::RTrees), trained by learn_shapes on the simulator's ground truth of randomised
/// scenes. Chosen over the hand-made decision of shape_fitter (a margin between plane and curved fits, settled by
/// the outline) because on unseen scenes no single cue holds: stereo smooths a sphere's cap flat in turbid
/// water, a box's faces share one shading under a lamp, the border cuts outlines. A forest weighs all cues
/// together, gives per-shape votes (a confidence) and predicts an object in well under a millisecond.

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include <string>
#include <vector>

#include "underwater_stereo/detection/forest_training.h"
#include "underwater_stereo/detection/forest_votes.h"
#include "underwater_stereo/detection/shape_kind.h"

namespace underwater_stereo {

struct ShapeVerdict {
  ShapeKind shape = ShapeKind::kUnknown;  ///< the shape with most votes
  double confidence = 0.0;                ///< share of the trees voting for it (0-1)
};

/// Training options of the shape model: deeper trees, and each shape weighted by (largest shape count / its
/// count)^balance.
struct ShapeModelTraining : ForestTraining {
  ShapeModelTraining() {
    max_depth = 12;
    balance = 1.0;
  }
};

class ShapeModel {
 public:
  ShapeModel() = default;
  /// Trains on `samples` (CV_32F, one row of kShapeFeatureCount features per object) with `labels` (sphere,
  /// cylinder, box or plane). @throw std::invalid_argument on mismatched sizes, an unknown label or a shape
  /// without any sample.
  static ShapeModel train(const cv::Mat& samples, const std::vector<ShapeKind>& labels, const ShapeModelTraining& options);
  /// @throw std::invalid_argument naming the file when it cannot be read or is not a model of these features.
  static ShapeModel load(const std::string& path);
  /// @throw std::runtime_error naming the file when it cannot be written.
  void save(const std::string& path) const;

  bool empty() const { return forest_.empty(); }
  /// The shape `features` (kShapeFeatureCount values, shapeFeatureNames() order) describe.
  /// @throw std::invalid_argument when features has the wrong size or the model is empty.
  ShapeVerdict classify(const std::vector<float>& features) const;

 private:
  cv::Ptr<cv::ml::RTrees> forest_;  ///< kept for save()
  ForestVotes votes_;               ///< the same trees, walked by classify()
};

}  // namespace underwater_stereo
