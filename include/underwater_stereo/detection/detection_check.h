// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The check after stereo: a second learnt model that judges whether each measured detection is an object of a
/// designated colour at all, or background (a distractor, the floor, a second view of one object), from what the
/// colour search saw (its proposal's features and the colour model's votes) and what stereo measured (range, size,
/// shape, how well it fitted, how much of it matched). The detection keeps the colour model's colour unless the check
/// is clearly surer of another designated one (colour_model.check_rename_margin) in a frame that is not dark:
/// renaming every detection had misnamed the fixed scenes' dark red and distant yellow buoys (docs/accuracy.md, "A
/// check after stereo" and "The check names colours").
///
/// The colour model judges every region of a frame at once, by its looks alone; the check judges only the
/// regions it passed, each with its 3D measurements, and is learnt (learn_checks) from the detector's own
/// detections of randomised scenes against their ground truth: the regions that reach it, labelled as the
/// evaluation counts them (the first detection of an object is its colour; a distractor, the background or a
/// second detection of one object is background). It is a colour model over checkFeatureNames() with boosted trees
/// (object_trees.h): they decide whether it is an object at all, its forest's per-colour votes name the colour. Boosted
/// trees were chosen over the forest for the decision by learning both from the same records and judging them on 2000
/// other pairs: more objects kept at every rate of false detections (docs/accuracy.md, "The check decides by boosted
/// trees").

#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "underwater_stereo/detection/colour_model.h"

namespace underwater_stereo {

/// What stereo measured of a detection, as the check reads it.
struct MeasuredForCheck {
  double range_m = 0;
  double largest_size_m = 0, smallest_size_m = 0;  ///< of the fitted shape's extents
  int shape = 0;                                   ///< static_cast<int>(ShapeKind)
  bool cut_by_border = false;
  double fit_rmse_m = 0;
  double matched_share = 0;  ///< of its mask's pixels, matched by stereo
};

/// The names of the check's features for a colour model of `colours`: a proposal's (blobFeatureNames()), the
/// colour model's share of votes for background and for each colour, then what stereo measured.
std::vector<std::string> checkFeatureNames(const std::vector<std::string>& colours);

/// The check's features of one detection: `colour_features` (its proposal's features followed by the colour
/// model's shares, Candidate::colour_features) and `measured`.
/// @throw std::invalid_argument when colour_features is empty (the candidate was not found by a colour model).
std::vector<float> checkFeatures(const std::vector<float>& colour_features, const MeasuredForCheck& measured);

/// How learn_checks learns a check: the forest that names colours, 100 trees of depth 12, unweighted; the boosted trees
/// that decide object or background, 400 of depth 6 (as good as 600 offline, and the check file stays under 2 MiB).
inline ColourModelTraining checkTraining() { return ColourModelTraining{{100, 12, 0.0, 1}, {400, 6}}; }

class DetectionCheck {
 public:
  DetectionCheck() = default;
  /// Learns from `samples` (CV_32F, one row of checkFeatureNames(colours) per detection) with `labels` (-1:
  /// background, k: an object of colours[k]); with `naming` (a forest over the same colours and features, e.g. of
  /// an earlier check) that forest names colours and only the boosted trees are learnt.
  /// @throw std::invalid_argument as ColourModel::train, on bad options (no boosted trees among them), or a `naming`
  /// of other colours.
  static DetectionCheck train(const cv::Mat& samples, const std::vector<int>& labels, const std::vector<std::string>& colours,
                              const ColourModelTraining& options, const ColourModel* naming = nullptr);
  /// The check in the file `path`, learnt over a colour model of `colours`.
  /// @throw std::invalid_argument naming the file when it cannot be read, is not a check of these colours' features,
  /// or holds no sound boosted trees (a check of an earlier build: learn it again).
  static DetectionCheck load(const std::string& path, const std::vector<std::string>& colours);
  /// @throw std::runtime_error naming the file when it cannot be written.
  void save(const std::string& path) const;

  bool empty() const { return !colours_.hasObjectTrees(); }
  /// The forest that names colours, with the boosted trees.
  const ColourModel& colours() const { return colours_; }
  /// How sure it is that a detection with `features` (checkFeatures) is an object, 0-1, above 0.5 an object: one half
  /// plus half the boosted trees' mean vote (each votes within [-1, 1]).
  /// @throw std::invalid_argument when features is empty or of another width, or the check is empty.
  double objectScore(const std::vector<float>& features) const;
  /// The forest's verdict on a detection with `features` (shares: background first; confidence: objectScore where the
  /// forest names a colour).
  /// @throw std::invalid_argument as objectScore.
  ColourVerdict colourVerdict(const std::vector<float>& features) const;

 private:
  /// @throw std::invalid_argument naming `caller` when the check is empty or `features` is not one row of its width.
  void requireFeatures(const std::vector<float>& features, const char* caller) const;

  ColourModel colours_;  ///< with boosted trees
  int width_ = 0;        ///< features per detection
};

}  // namespace underwater_stereo
