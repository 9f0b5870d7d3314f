// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Why a labelled object was not found by the learned colour search (learn_colours' table of misses):
/// no proposal covered it, the forest gave its colour too few votes, named it another colour, or its region
/// passed the forest and was then taken by a more confident overlapping one.

#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "underwater_stereo/detection/colour_learning.h"
#include "underwater_stereo/detection/colour_model.h"

namespace underwater_stereo {

/// The stage that lost a labelled object, in the order of the search.
enum class MissCause {
  kNoProposal,      ///< no proposal covers it (intersection over union under kMatchIou)
  kUnderThreshold,  ///< covered, but no covering region got its colour's min_confidence (nor another colour's)
  kWrongColour,     ///< a covering region was reported as another colour (and none as its own)
  kOverlapped,      ///< a covering region passed as its colour, then lost to a more confident overlapping one of
                    ///< the same colour centred off the label (merged with its surroundings or a neighbour)
  kOffLabel,        ///< passed as its colour and not overlapped, but its detection's centre left the label
};
constexpr int kMissCauseCount = 5;

/// Short name of a cause (table rows).
std::string missCauseName(MissCause cause);

/// Why a label of colour `colour` (index into the model's colours) was missed, and the most votes a covering
/// region got for that colour (0 when none was named it).
struct MissExplanation {
  MissCause cause = MissCause::kNoProposal;
  double best_confidence = 0;
};

/// A detection as explainMiss sees it: its box and colour (index into the model's colours).
struct KeptRegion {
  cv::Rect roi;
  int colour = -1;
};

/// From the frame's proposal boxes with the forest's verdict on each (same order), its detections, the
/// per-colour thresholds and the detector's colour_model.max_overlap.
/// @throw std::invalid_argument when the proposals and verdicts, or thresholds and colour, do not match.
MissExplanation explainMiss(const cv::Rect& label, int colour, const std::vector<cv::Rect>& proposals,
                            const std::vector<ColourVerdict>& verdicts, const std::vector<KeptRegion>& detections,
                            const std::vector<double>& min_confidence, double max_overlap);

/// One missed label, where and why.
struct Miss {
  std::string frame;
  LabelBox label;
  int colour = 0;
  MissExplanation why;
};

/// Every counted label (>= options.min_label_px tall) of `frames` that `detections` (detectionsOf(detector,
/// frames)) miss at `min_confidence` per colour, each explained with the detector's own proposals and model.
/// @throw std::invalid_argument when the detector has no learned colour model or the counts do not match.
std::vector<Miss> explainMisses(const Detector& detector, const std::vector<LabelledFrame>& frames,
                                const std::vector<std::vector<Detection>>& detections, const LearningOptions& options,
                                const std::vector<double>& min_confidence);

}  // namespace underwater_stereo
