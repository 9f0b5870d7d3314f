// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The detector judged on sampled scenes: per-object records against the simulator's exact truth, tables
// broken down by range, turbidity, brightness, colour and shape, JSON records and pictures of the worst failures.
#include <opencv2/core.hpp>

#include <cstdint>
#include <functional>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/sim/renderer.h"
#include "underwater_stereo/sim/scene_sampler.h"

namespace underwater_stereo {
namespace tools {

/// Objects count when of a designated colour, 0.5-5 m away and with >= 400 visible pixels (as in the scene-file
/// mode); their shape counts from 1500 pixels on.
constexpr int kMinVisiblePixels = 400, kMinShapePixels = 1500;
constexpr double kMinRangeM = 0.5, kMaxRangeM = 5.0;

/// One truth object of one pair and what the detector made of it.
struct ObjectRecord {
  std::string name, colour;
  ShapeKind shape = ShapeKind::kUnknown;
  bool designated = false, eligible = false;
  double range_m = 0.0;
  int visible_pixels = 0;
  bool cut_by_border = false;       ///< its pixels touch the image border
  cv::Rect roi;                     ///< truth box in the raw left image
  Eigen::Vector3d albedo = Eigen::Vector3d::Zero(), size_m = Eigen::Vector3d::Zero(),
                  centre_m = Eigen::Vector3d::Zero();
  double transmission = 0.0;        ///< mean over r, g, b of exp(-attenuation * range): how much water hides it
  bool found = false;
  std::string detected_colour;
  ShapeKind detected_shape = ShapeKind::kUnknown;
  double detected_range_m = 0.0;
  Eigen::Vector3d detected_centre_m = Eigen::Vector3d::Zero();
  cv::Rect detected_roi;
  double range_error = 0.0;         ///< |range - true| / true range (found only)
  double position_error = 0.0;      ///< |centre - true centre| / true range (found only)
  std::vector<float> detected_shape_features;  ///< Detection::shape_features (what learn-shapes trains on)
  std::vector<float> detected_check_features;  ///< Detection::check_features (what learn_checks trains on)
  /// Of a missed eligible object, the last stage that lost it (missCauseNames()), and that rejection's own words
  /// (Rejection::reason, e.g. how many 3D points or the check's score; "" when it gave none).
  std::string miss_cause, miss_reason;
};

/// A detection that is no eligible designated object (background, a distractor, a second detection of one object).
struct FalseRecord {
  std::string colour;
  ShapeKind shape = ShapeKind::kUnknown;
  std::string on;  ///< the truth object it lies on, "" for background
  cv::Rect roi;
  double range_m = 0.0;
  std::vector<float> check_features;  ///< Detection::check_features (what learn_checks trains on)
};

struct PairRecord {
  std::uint64_t seed = 0;
  double turbidity = 0.0, water_type = 0.0, target_luma = 0.0;
  double luma = 0.0;                ///< mean BT.601 luma of the demosaiced left image
  double focal_px = 0.0;            ///< [px] the head's focal length in water (its optics: --focal-mm)
  double baseline_m = 0.0;          ///< [m] the head's baseline (--baseline-m)
  std::string quality;              ///< the detector's quality status
  double render_ms = 0.0, detect_ms = 0.0;
  bool looks_swapped = false;       ///< the detector took it for a pair in the wrong order (DetectionResult)
  std::vector<ObjectRecord> objects;
  std::vector<FalseRecord> false_detections;
};

/// Why a missed object was missed, as named in ObjectRecord::miss_cause: "frame spoiled" (the quality gate
/// reported the frame and nothing was searched); the latest RejectionStage (rejectionStageName) of the detector's
/// rejections on it; else "no votes": no region on it got even half the votes a colour needs, none was proposed,
/// or its region was passed over as a weaker view of a kept candidate. In that order.
const std::vector<std::string>& missCauseNames();

/// A box matches a truth object's box by intersection over union from this (PASCAL VOC's rule).
constexpr double kSameBoxIou = 0.5;

/// The truth object (index into `objects`, each one's `roi` and `visible_pixels` set) a box `roi` of the left image
/// lies on, or -1. Of the objects with at least 20 % of the smaller of box and object in it (truth pixels): the one
/// whose box it matches best by intersection over union, from kSameBoxIou (ties: the first); else the one with most
/// pixels in it (a detection of part of an object). `labels`: the left image's truth labels (CV_16UC1, object k as
/// k + 1, 0 none). Boxes first: a partly hidden object's detection lies on it, not on the nearer object whose pixels
/// fill more of its box. @throw std::invalid_argument when labels is not CV_16UC1.
int objectUnder(const cv::Mat& labels, const std::vector<ObjectRecord>& objects, const cv::Rect& roi);

/// Matches detections to the truth: a detection belongs to the object under its box (objectUnder); the first
/// detection of an object counts, others and those on no eligible object are false, those on designated objects that
/// are not eligible (too small, too near or far) are neither. A missed eligible object gets its miss_cause from the
/// rejections matched to it by the same rule.
/// @throw std::invalid_argument when a truth object's shape is no ShapeKind name.
PairRecord evaluatePair(const sim::SampledScene& sampled, const sim::RenderedPair& pair, const DetectionResult& result,
                        double luma);

/// The records of pairs 0..pairs-1, each made by `run(i)`, `jobs` at a time; a pair whose run throws is listed with
/// its message and the others still run (nothing already computed is lost).
struct PairRuns {
  std::vector<PairRecord> records;                     ///< the pairs that ran, in index order
  std::vector<std::pair<int, std::string>> failures;  ///< (index, what it threw), in index order
};
PairRuns runPairs(int pairs, int jobs, const std::function<PairRecord(int)>& run);

/// Markdown tables: overall, then per range, turbidity, brightness, water, colour and shape bin.
void printSummary(std::ostream& out, const std::vector<PairRecord>& pairs);

/// Every pair with every object and false detection, as one JSON document.
void writeJson(std::ostream& out, const std::vector<PairRecord>& pairs, const std::string& config_path);

/// The `k` worst failures (missed, then colour wrong, then shape wrong, then largest range error), worst first:
/// (pair index, object index).
std::vector<std::pair<std::size_t, std::size_t>> worstFailures(const std::vector<PairRecord>& pairs, std::size_t k);

/// The left image with the truth box (green) of `object`, every detection (red) and a caption.
cv::Mat failurePicture(const cv::Mat& left_bgr, const PairRecord& pair, const ObjectRecord& object,
                       const DetectionResult& result);

}  // namespace tools
}  // namespace underwater_stereo
