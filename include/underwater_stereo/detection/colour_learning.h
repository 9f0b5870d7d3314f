// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Learning the designated colours from labelled frames (learn_colours): Pascal VOC labels, samples
/// from the detector's own proposals, k-fold cross-validation by frame.

#include <opencv2/core.hpp>

#include <map>
#include <string>
#include <vector>

#include "underwater_stereo/detection/colour_model.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/detection/detector_config.h"
#include "underwater_stereo/detection/learned_candidates.h"

namespace underwater_stereo {

/// One labelled box of a frame.
struct LabelBox {
  std::string name;  ///< the label as written (buoy_red)
  cv::Rect box;      ///< image pixels
};

/// A proposal is an example of a labelled object (and covers it) when their boxes overlap by this much.
constexpr double kMatchIou = 0.3;

/// Whether the centre of `roi` lies in `box` (edges included): how a detection finds a label.
bool centreInside(const cv::Rect& roi, const cv::Rect& box);

/// The `<object>`s of a Pascal VOC annotation file (read as XML: comments, attributes and a `<part>`'s own box
/// are no objects). @throw std::invalid_argument naming the file (and the object's number and name) when it
/// cannot be read, is not VOC XML (or holds a second root element after its <annotation>), an object has two
/// <name>, <bndbox> or corners of one kind, or a box is empty, not a number, beyond any image (16384 px) or
/// (nearly: 0.9 of their union) another object's box too. `declared_size`, when given, receives the image size its <size> declares (empty when it
/// declares none, or a side of 0); a <size> whose <width> or <height> is no whole number, or a <size>, <width> or
/// <height> given twice, is an error too.
std::vector<LabelBox> readVocLabels(const std::string& path, cv::Size* declared_size = nullptr);

/// A frame to learn from: its image and labels.
struct LabelledFrame {
  std::string name;   ///< for messages (the image's path)
  cv::Mat image;      ///< 8-bit BGR
  std::vector<LabelBox> labels;
  cv::Size declared_size;  ///< the image size its annotation declares (empty: none declared)
};

struct LearningOptions {
  std::vector<std::string> colours;             ///< colours to learn (designated colour names)
  std::vector<std::string> background_labels;   ///< other label names, learnt as background
  /// Labelled objects shorter than this [px] lie beyond the working range: neither targets nor background.
  int min_label_px = 15;
  /// Each frame is also learnt from this many copies seen through other water (augmentedWater()).
  int augment = 2;
  /// And from this many copies seen nearer (zoomedIn()): near objects are few in most labelled sets.
  int zoom = 0;
  ColourModelTraining training;

  std::vector<std::string> validate() const;
};

/// The colour index (into options.colours) a label teaches: its name, or the part after its last '_'
/// (buoy_red -> red); -1 for a background label. @throw std::invalid_argument for any other name.
int colourOfLabel(const std::string& name, const LearningOptions& options);

/// What is wrong with the frames' labels (colour or background name, box inside the image, the annotation's declared
/// size the image's) and the options, and, with `coverage`, every colour without an example it can learn from (a
/// label under min_label_px teaches nothing: those are named): each problem with file and box. Without `coverage`
/// for frames some of which could not be read (their labels unknown).
std::vector<std::string> labelProblems(const std::vector<LabelledFrame>& frames, const LearningOptions& options,
                                       bool coverage = true);
/// @throw std::invalid_argument listing every labelProblems() when there are any.
void checkLabels(const std::vector<LabelledFrame>& frames, const LearningOptions& options);

/// `bgr` as if seen through other water, drawn from `seed`: the water's veil over it deepened towards a
/// random water colour (up to 35 %), per-channel gains of 0.75-1.3 (white balance, attenuation) and an
/// overall exposure of 0.7-1.3. Labels stay valid (no geometry changes).
cv::Mat augmentedWater(const cv::Mat& bgr, unsigned seed);

/// `frame` as if seen from nearer, drawn from `seed`: enlarged 1.3-2x and cut back to its size around one of its
/// labelled objects of a colour (anywhere when it has none); labels scaled, clipped to the window, those outside
/// it dropped.
LabelledFrame zoomedIn(const LabelledFrame& frame, unsigned seed, const LearningOptions& options);

/// Training rows of one frame: the detector's proposals with their features and label (-1 background,
/// k colour k); proposals that half-overlap a labelled object, or overlap a too-small one, are left out.
struct FrameSamples {
  cv::Mat features;          ///< CV_32F, one row per sample
  std::vector<int> labels;
  int objects = 0;           ///< labelled objects of a colour, >= min_label_px tall
  int proposed = 0;          ///< of them, those some proposal matches (the most the model can find)
};
/// With options.augment > 0, the rows of the frame's augmented copies (seeds from `seed`) are added.
FrameSamples samplesOf(const LabelledFrame& frame, const Detector& proposer, const LearningOptions& options,
                       unsigned seed = 1);

/// The colour model learnt from every sample of `parts` (options.colours, options.training).
/// @throw std::invalid_argument as ColourModel::train (no background, a colour without samples).
ColourModel learnColourModel(const std::vector<const FrameSamples*>& parts, const LearningOptions& options);

/// Recall, false detections and confusions of a config on held-out frames.
struct LearningScore {
  std::vector<int> labelled, found;  ///< per colour (labels >= min_label_px)
  int frames = 0;
  int false_detections = 0;          ///< detections matching no label of their colour (nor a small one)
  std::vector<int> false_by_colour;  ///< of them, per detected colour (options.colours' order)
  /// confusion[true colour][detected colour]; the last column counts missed labels.
  std::vector<std::vector<int>> confusion;
  void add(const LearningScore& other);
  double recall() const;
};
/// Runs `detector` (2D) on `frames` and scores it: a label is found when a detection of its colour has its
/// box centre inside the label's box.
LearningScore score(const Detector& detector, const std::vector<LabelledFrame>& frames, const LearningOptions& options);

/// The same at each of `min_confidences` (ascending, none under the detector's colour_model.min_confidence),
/// from one detection pass: a detection counts at a threshold when its confidence reaches it. Equal to
/// detectors configured with each threshold, since a region is only ever suppressed by a more confident one.
std::vector<LearningScore> scoreAt(const Detector& detector, const std::vector<LabelledFrame>& frames,
                                   const LearningOptions& options, const std::vector<double>& min_confidences);

/// Each frame's 2D detections (Detector::detect2d), in the frames' order.
std::vector<std::vector<Detection>> detectionsOf(const Detector& detector, const std::vector<LabelledFrame>& frames);

/// Scores `detections` (one list per frame) counting those of colour k with confidence >= min_confidence[k].
/// @throw std::invalid_argument when the counts of lists or thresholds do not match.
LearningScore scoreDetections(const std::vector<LabelledFrame>& frames,
                              const std::vector<std::vector<Detection>>& detections, const LearningOptions& options,
                              const std::vector<double>& min_confidence);

/// Per-colour thresholds and their score.
struct ThresholdChoice {
  std::vector<double> min_confidence;  ///< one per colour (options.colours' order)
  LearningScore score;
};
/// Of every combination of per-colour thresholds from `grid`, the one with the best mean per-colour recall (then
/// overall recall, then fewest false) among those with at most `max_false_per_frame` false detections per frame
/// (the fewest false when none has so few). `detections` must come from a detector whose thresholds are at most
/// grid's smallest; a region suppressed there by a more confident one of another colour stays suppressed.
/// @throw std::invalid_argument when there are more than 1e5 combinations.
ThresholdChoice chooseThresholds(const std::vector<LabelledFrame>& frames,
                                 const std::vector<std::vector<Detection>>& detections, const LearningOptions& options,
                                 const std::vector<double>& grid, double max_false_per_frame);

/// `base` as a proposer of regions to learn from (Detector::proposals): its search settings, with HSV candidates
/// (so that no colour model is needed) and no check after stereo (it reads a colour model's votes).
DetectorConfig proposerConfig(const DetectorConfig& base);

/// `base` with candidates.source learned and `model` (loaded from `model_file`), colours = options.colours
/// (the base's entries kept for colours it has, but their min_confidence: the base model's), and no check after
/// stereo (the base's reads the base model's votes).
DetectorConfig learnedConfig(const DetectorConfig& base, const std::string& model_file,
                             std::shared_ptr<const ColourModel> model, const LearningOptions& options);

}  // namespace underwater_stereo
