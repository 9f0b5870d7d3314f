// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The whole pipeline on one stereo pair: quality, colour, 2D candidates, ROI stereo, clustering, shape.

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "underwater_stereo/detection/detector_config.h"
#include "underwater_stereo/detection/outline_kind.h"
#include "underwater_stereo/detection/raw_frame.h"
#include "underwater_stereo/detection/shape_kind.h"
#include "underwater_stereo/detection/stereo_order.h"
#include "underwater_stereo/common/stereo_calibration.h"

namespace underwater_stereo {

/// One object found in a pair. Frames: left optical frame (x right, y down, z forward).
struct Detection {
  std::string colour;                 ///< designated colour class
  cv::Scalar measured_bgr;            ///< mean B, G, R (0-255) of its pixels in the raw left image
  ShapeKind shape = ShapeKind::kUnknown;
  OutlineKind outline = OutlineKind::kPolygon;  ///< of its 2D contour
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();   ///< as DetectedObject.size
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  double range_m = 0.0;               ///< |position_m|
  cv::Rect roi;                       ///< raw left image
  std::vector<cv::Point> contour;     ///< raw left image
  /// Its outline runs along the image's border (onImageBorder): the object is partly out of view, and its
  /// size and position are partly a guess at what is not seen.
  bool cut_by_border = false;
  double confidence = 0.0;            ///< 0-1
  std::vector<Eigen::Vector3f> points;  ///< the object's cluster [m]
  double fit_rmse_m = 0.0;
  std::vector<float> shape_features;  ///< what the shape was decided from (shapeFeatureNames()); empty: too few points
  /// What the check after stereo reads (checkFeatures, detection_check.h; what learn_checks learns from); empty
  /// when no colour model found it.
  std::vector<float> check_features;
};

/// Time per stage of the last call [ms]; the per-object stages (rectify: silhouette disparity and band
/// rectification; matching: block matching; reprojection; cluster; fit; and the right frame's colour mask, part
/// of colour) are summed over objects (measured in parallel), so they can add up to more than total_ms.
struct StageTimings {
  double quality_ms = 0, colour_ms = 0, contours_ms = 0, rectify_ms = 0, matching_ms = 0, reprojection_ms = 0,
         cluster_ms = 0, fit_ms = 0, total_ms = 0;
};

struct DetectionResult {
  QualityReport quality;
  std::vector<Detection> objects;
  /// Regions looked at and not reported, with why (learned colours: colour too uncertain; any source: too
  /// few 3D points, wrong metric size for its colour...).
  std::vector<Rejection> rejected;
  /// The pair looks as if its left and right images came swapped (stereo_order.h, PairOrder): none of its
  /// objects is reported; those that would have been, and those stereo turned down, are rejected as
  /// RejectionStage::kLeftRightSwapped.
  bool looks_swapped = false;
  /// The scale the 2D search ran at: search_scale, or a dark frame's (dark_search_width_px, learned source).
  double search_scale = 0.0;
  StageTimings timings;
};

/// Runs the pipeline. detect() and detect2d() only read the detector (its configuration and rectification
/// maps): one instance may serve several threads at once.
class Detector {
 public:
  /// 3D detector. @throw std::invalid_argument when the config or calibration does not validate.
  Detector(const DetectorConfig& config, const StereoCalibration& calibration);
  /// 2D-only detector (no calibration): detect2d() only. @throw std::invalid_argument on invalid config.
  explicit Detector(const DetectorConfig& config);
  ~Detector();

  /// Raw (distorted) left and right frames of the calibrated size, as they arrive (BGR8, grey or Bayer: a
  /// cv::Mat converts to a BGR or grey RawFrame). A spoiled frame is reported with no objects.
  /// @throw std::invalid_argument on empty frames or wrong sizes, when built without calibration, or when the two
  /// frames are the same image and the left holds a candidate (its range would be made up).
  DetectionResult detect(const RawFrame& left, const RawFrame& right) const;
  /// Quality, colour and 2D candidates only (colour, outline, roi, measured colour; no 3D fields).
  /// @throw std::invalid_argument when `frame` is empty.
  DetectionResult detect2d(const RawFrame& frame) const;

  /// The regions the learned colour search weighs in `frame`, not their pieces (cutIntoPieces) (full-resolution
  /// pixels; contours and masks stay in the searched image's), with the features a colour model names them from:
  /// what learn_colours trains on. Empty for a spoiled frame. @throw std::invalid_argument when `frame` is empty.
  std::vector<BlobProposal> proposals(const RawFrame& frame) const;

  const DetectorConfig& config() const { return config_; }

  /// What a user should know about the workspace with this calibration: "" when stereo searches all of
  /// stereo.min_depth_m .. max_depth_m (and for a 2D-only detector); else which near depths are not ranged and
  /// why (a long baseline or lens: RoiStereoMatcher::nearestDepthM).
  std::string workspaceNote() const;

 private:
  /// What the check after stereo (colour_model.check_file) may do with a measured candidate besides scoring it.
  struct CheckUse {
    bool may_rename = true;  ///< name its colour: not in a dark frame (quality.enhanced), whose colours it learnt few of
    /// turn it down: not a region joined from pieces that each passed it (the join is a matter of geometry)
    bool may_reject = true;
  };

  /// Stereo, clustering and shape of one candidate (the masks and `agreement` as RoiStereoMatcher::match takes them).
  std::optional<Detection> measure(const Candidate& c, const RawFrame& left, const RawFrame& right,
                                   const cv::Mat& right_colour, const cv::Point& right_colour_origin,
                                   const cv::Mat& left_colour, const ViewAgreement& agreement, CheckUse check_use,
                                   StageTimings& t, Rejection& rejected, ObjectOrderEvidence* order = nullptr) const;

  DetectorConfig config_;
  DetectorConfig search_config_;  ///< config_ scaled for the 2D search (scaledForSearch at search_scale)
  std::unique_ptr<RoiStereoMatcher> matcher_;
};

}  // namespace underwater_stereo
