// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The check after stereo: a second colour model that judges whether each measured detection is an object of a
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
/// second detection of one object is background). Learnt over OpenCV's random trees as the colour model is
/// (ColourModel over checkFeatureNames()), measured against the colour model alone in docs/accuracy.md.

#include <string>
#include <vector>

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

}  // namespace underwater_stereo
