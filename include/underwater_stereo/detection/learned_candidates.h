// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Step 3 with a learnt colour model: regions that stand out from the water, named by the model,
/// verified, overlapping proposals of one object merged.

#include <opencv2/core.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "underwater_stereo/detection/blob_proposals.h"
#include "underwater_stereo/detection/candidate_finder.h"
#include "underwater_stereo/detection/colour_model.h"
#include "underwater_stereo/detection/colour_segmenter.h"
#include "underwater_stereo/detection/detection_check.h"
#include "underwater_stereo/detection/water_contrast.h"

namespace underwater_stereo {

/// The `colour_model` section of the detector configuration (candidates.source: learned).
struct LearnedColourConfig {
  std::string file;             ///< the model's file (learn_colours writes it), resolved against the config's folder
  /// Confidence the model must have in a colour: the share of trees voting for it, or with boosted trees their score
  /// (0.45: chosen for the default model, a forest, on the validation seeds 60000-60299, docs/accuracy.md;
  /// config/detector.yaml says the same).
  double min_confidence = 0.45;
  /// A proposal overlapping a more confident one by more than this share of the smaller box is the same object.
  double max_overlap = 0.3;
  WaterContrastConfig water;
  ProposalConfig proposals;     ///< areas in full-resolution pixels, like candidates.min_area_px
  std::shared_ptr<const ColourModel> model;  ///< loaded from `file`
  /// The check after stereo (detection_check.h; learn_checks writes it), resolved like `file`; empty: none.
  std::string check_file;
  /// How sure the check must be that a detection is an object (any colour, not background) for it to be reported:
  /// DetectionCheck::objectScore, 0-1, 0.5 where the boosted trees' votes even out.
  double check_min_confidence = 0.5;
  /// With a check, regions with this confidence of the colour model (its share of the votes, or its boosted trees'
  /// score) go on to stereo and the check (in place of
  /// min_confidence, which stays the decision where nothing is measured in 3D: detect2d, detect_files --image).
  double check_from_confidence = 0.2;
  /// With a check, a detection takes the check's colour when the check's share of votes for it exceeds its share for
  /// the colour model's colour by more than this (1: the colour model's colour always). Not in a dark frame (darker than
  /// quality.enhance_below): the check learnt the colours of few such frames and misnames them.
  double check_rename_margin = 0.15;
  std::shared_ptr<const DetectionCheck> check;  ///< loaded from `check_file`, over checkFeatureNames(model->colours())

  std::vector<std::string> validate() const;
};

/// Intersection over union of two boxes.
double boxIou(const cv::Rect& a, const cv::Rect& b);
/// Intersection over the smaller box's area.
double overlapOfSmaller(const cv::Rect& a, const cv::Rect& b);
/// Whether two regions (boxes and their CV_8UC1 box-sized masks, in one image) are views of one object: their
/// boxes and their masks both overlap more than `max_overlap` (colour_model.max_overlap) of the smaller. A region
/// inside another's box but not on its pixels (a small object in front of a large one, beside its outline) is
/// another object.
bool sameRegion(const cv::Rect& a, const cv::Mat& a_mask, const cv::Rect& b, const cv::Mat& b_mask, double max_overlap);

/// The stage that turned a region down, in the order of the pipeline.
enum class RejectionStage {
  kColourNotDesignated,  ///< the model names a colour this configuration does not designate
  kColourUncertain,      ///< its colour's votes under that colour's min_confidence
  kTooManyCandidates,    ///< beyond candidates.max_candidates
  kNotSeenByRight,       ///< the right frame does not show it where its points matched (RoiPoints::unseen)
  kBeyondFarEnd,         ///< stereo matched it beyond the workspace's far end (RoiPoints::beyond_far_end)
  kTooFewPoints,         ///< too few 3D points in its main cluster
  kNoFit,                ///< the shape fit gave no finite position or size
  kWrongSize,            ///< metric size outside its colour's configured range
  kCheckAfterStereo,     ///< the check after stereo (colour_model.check_file) takes it for background
  kLeftRightSwapped,     ///< its pair looks as if left and right images were swapped (stereo_order.h)
  kPieceOfObject,        ///< measured again as part of a larger detection of its colour
};
constexpr int kRejectionStageCount = static_cast<int>(RejectionStage::kPieceOfObject) + 1;

/// Whether `stage` turned a region down after it was measured in 3D (kNotSeenByRight to kCheckAfterStereo).
bool turnedDownByStereo(RejectionStage stage);

/// Short name of a stage ("colour uncertain", "too few 3D points"...).
std::string rejectionStageName(RejectionStage stage);

/// A region the detector looked at and did not report, with why (detect_files --explain, diagnostics).
struct Rejection {
  cv::Rect roi;          ///< raw image pixels
  std::string colour;    ///< the colour it was taken for (empty: none)
  /// How sure what turned it down was of it: the colour search's confidence; for kCheckAfterStereo the check's
  /// object score; for kPieceOfObject and kLeftRightSwapped the confidence it would have been reported with (one
  /// stereo turned down in a pair taken for swapped keeps what turned it down).
  double confidence = 0;
  RejectionStage stage = RejectionStage::kColourUncertain;
  std::string reason;    ///< the stage's particulars, for a person
};

struct LearnedSearch {
  WaterContrast contrast;  ///< of the searched image (its stats measure the right frame alike)
  std::vector<Candidate> candidates;  ///< most confident first, at most candidates.max_candidates
  /// For each candidate, the most confident view skipped as the same object (sameRegion), if any: what the detector
  /// measures in its place when the candidate is turned down after stereo (turnedDownByStereo: a region of an object
  /// and what it touches, turned down, while the object's own piece or region was skipped as part of it).
  std::vector<std::optional<Candidate>> second_views;
  /// For each candidate that is a piece standing in place of its region (the region held pieces of two colours, or two
  /// pieces of one: two objects, or one cut in two), that region as an index into `wholes`, else -1: what the
  /// detector measures when all of that region's pieces prove one object in 3D (joinPieces), in place of their union.
  /// Only with OneColourPieces::kPiecesStand; all -1 with kRegionStands.
  std::vector<int> whole_of;
  /// Those regions, described as candidates are (searched-image pixels; the detector's FrontEnd holds them at full
  /// resolution); colour_index is the region's own colour (-1 where none is designated), which the detector replaces
  /// by its pieces'.
  std::vector<Candidate> wholes;
  std::vector<Rejection> rejected;    ///< proposals some colour got votes for, not reported (searched-image pixels)
};

/// The water contrast of `bgr` (the searched image) and the regions proposed in it within the candidates' area
/// limits: what findLearnedCandidates names (with the pieces it cuts some into), and what learn_colours learns from.
struct LearnedProposals {
  WaterContrast contrast;
  std::vector<BlobProposal> regions;
};
/// On `threads` threads (workOnThreads; the same result whatever the number).
/// @throw std::invalid_argument when bgr is not CV_8UC3 or a config is invalid.
LearnedProposals proposeLearned(const cv::Mat& bgr, const LearnedColourConfig& config, const CandidateConfig& candidates,
                                int threads = 1);

/// What stands for the objects of a region cut into two pieces of one colour (two objects of one colour touching in
/// the image, or one object cut in two by a shading band or a box's edge).
enum class OneColourPieces {
  kRegionStands,  ///< the region: in one image nothing tells the two cases apart (detect2d)
  kPiecesStand,   ///< its pieces, in its place: stereo tells them apart (the detector measures them whole again when
                  ///< their 3D clusters touch, joinPieces)
};

/// Candidates of `bgr` (the searched image). A proposal's colour must be one of `classes` (the designated
/// colours, by name) and the model's confidence in it (ColourVerdict::confidence) must reach the class's
/// min_confidence, else the model's (with `for_check`, config.check_from_confidence for every colour: the check after
/// stereo decides). A region cut into pieces of two colours gives way to its pieces; one cut into two pieces of one
/// colour as `one_colour` says. On `threads` threads (workOnThreads; the same result whatever the number).
/// @throw std::invalid_argument when bgr is not CV_8UC3 or the model is missing.
LearnedSearch findLearnedCandidates(const cv::Mat& bgr, const std::vector<ColourClass>& classes,
                                    const LearnedColourConfig& config, const CandidateConfig& candidates, int threads = 1,
                                    bool for_check = false, OneColourPieces one_colour = OneColourPieces::kRegionStands);

}  // namespace underwater_stereo
