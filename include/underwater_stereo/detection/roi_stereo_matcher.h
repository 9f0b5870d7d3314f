// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Step 4 of the pipeline: stereo matching only inside a region of interest.
///
/// Rectification maps for the whole frame are computed once from the calibration. Per candidate: the
/// disparity of its colour silhouette (left mask against the right frame's colour mask, over the
/// workspace's disparity range), then only the band of rows it covers is rectified (both cameras, only
/// the raw pixels the band reads are converted to grey), matched with semi-global block matching over the
/// disparities of the object's expected depth relief around the silhouette's, and its pixels reprojected
/// to 3D, but those the two raw frames show in other colours (StereoMatchConfig::max_colour_difference), and
/// none when the right camera does not see the object where it matched (StereoMatchConfig::max_unseen_share).

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "underwater_stereo/detection/raw_frame.h"
#include "underwater_stereo/detection/stereo_order.h"
#include "underwater_stereo/detection/water_contrast.h"
#include "underwater_stereo/common/stereo_calibration.h"

namespace underwater_stereo {

struct StereoMatchConfig {
  double min_depth_m = 0.5;    ///< [m] workspace: nearest depth searched (largest disparity; RoiStereoMatcher::nearestDepthM)
  double max_depth_m = 5.0;    ///< [m] farthest depth searched
  int block_size = 5;          ///< SGBM block (odd, 3..11)
  int uniqueness_ratio = 5;    ///< SGBM: best cost must beat the second by this percentage
  int margin_px = 12;          ///< context around the ROI for matching
  int erode_px = 3;            ///< shrink the object's mask by this much (disparities at its edge are unreliable)
  int max_points = 1500;       ///< mask pixels are sampled on a grid to at most about this many points
  /// A sampled point whose colour the two cameras see this far apart (chromaticity: half the summed absolute
  /// difference of the channels' shares, around 6x6 raw pixels; 0-1) was matched onto something else, most often
  /// a nearer object hiding it from the right camera: it is dropped (1: never; nor where either frame is grey, or
  /// too dark to tell there, or the match lies outside either raw frame).
  double max_colour_difference = 0.05;
  /// A candidate more than this share of whose compared points do not stand out from the water in the right frame
  /// where they matched (RoiPoints::unseen_points) is not seen there by the right camera: no point is kept. 1: never
  /// (nor where either frame is grey, or without a ViewAgreement).
  double max_unseen_share = 0.5;

  std::vector<std::string> validate() const;
};

/// How a candidate stood out from the water in the left frame (its saliency: WaterContrast), for asking whether the
/// right frame shows it where its points matched. A point matched onto something else (the water beside the object,
/// or a nearer object that hides it from the right camera) does not stand out from the water there as the object's
/// left view does.
struct ViewAgreement {
  cv::Mat water;              ///< the left frame's water colour (WaterContrast::water, BGR8); empty: no check
  double water_scale = 1;     ///< its size over the raw frame's
  ContrastStats stats;        ///< the left frame's spreads (WaterContrast::stats)
  SaliencyKind kind = SaliencyKind::kFull;  ///< the candidate's saliency kind
  double ratio_offset = 1;    ///< WaterContrastConfig::ratio_offset: contrast is ln((I + offset) / (water + offset))
  double level = 0;           ///< the candidate's saliency level [spreads]
};

/// 3D points of one region, in the left camera's (unrectified) optical frame.
struct RoiPoints {
  std::vector<Eigen::Vector3f> points;  ///< [m]
  int mask_pixels = 0;                  ///< object pixels in the rectified band (after erosion)
  /// Of those, with a valid disparity inside the workspace (and the right image), before the colour check.
  int matched_pixels = 0;
  /// Sampled points dropped because the right camera sees them in another colour
  /// (StereoMatchConfig::max_colour_difference).
  int other_colour_points = 0;
  /// Of the sampled points whose left view stands out from the water at the candidate's level (ViewAgreement;
  /// `compared_points`, both views inside their raw frames), those whose right view does not stand out from the same
  /// water by half of it (`unseen_points`). More than StereoMatchConfig::max_unseen_share of them, of at least 10
  /// compared (`unseen`): the right camera does not see the object where it was matched (a nearer object hides it, or
  /// it lies beyond the right frame), and no point is kept.
  int unseen_points = 0, compared_points = 0;
  bool unseen = false;
  /// Disparity [px] of the object's colour silhouette: how far its outline shifts between the rectified left
  /// and right colour masks (sub-pixel, from the masks' column profiles). A sphere's outline is the tangent
  /// cone around its centre and a cylinder's the tangent lines of its axis, so this is the depth of the centre
  /// or axis, free of the smoothing that flattens stereo surfaces. NaN when no right mask was given or the
  /// silhouette was not found in it.
  double silhouette_disparity = std::numeric_limits<double>::quiet_NaN();
  /// Disparities block matching searched at full size: a window around the silhouette's disparity, else around
  /// the median of a half-size search over the workspace and beyond its far end (workspaceAndBeyond), else (too few
  /// half-size matches) that band at full size (reprojection keeps what lies in the workspace); 0 when the object
  /// lies beyond the far end (beyond_far_end);
  /// never more than the box's right edge allows (a pixel at column x is in the right image up to disparity x).
  /// 0 when nothing was matched.
  int searched_disparities = 0;
  /// The window (around the silhouette's or the half-size search's disparity) missed: most matches lay at its ends,
  /// so the whole workspace was searched (searched_disparities counts that search).
  bool window_missed = false;
  /// Without a silhouette, the half-size search (which also looks beyond the workspace's far end,
  /// StereoMatchConfig::max_depth_m, to about twice its depth) matched most of the object's pixels, agreeing, clearly
  /// beyond it: the object lies farther. Nothing is matched at full size and no point is kept.
  bool beyond_far_end = false;
  /// Wall time [ms] of the steps: silhouette disparity, the half-size search and rectifying the band (grey and
  /// mask), block matching, reprojecting the mask's pixels (with the colour check).
  double rectify_ms = 0, matching_ms = 0, reprojection_ms = 0;
};

class RoiStereoMatcher {
 public:
  /// @throw std::invalid_argument when the calibration or config does not validate.
  RoiStereoMatcher(const StereoCalibration& calibration, const StereoMatchConfig& config);

  /// Matches the object given by `mask` (CV_8UC1 the size of `roi`, raw left image coordinates).
  /// `left`/`right` are raw (distorted) frames of the calibrated size (only the pixels the bands read are
  /// converted to grey; the colour check reads both at half size around the sampled points). `right_colour`
  /// (optional: empty to skip) is the raw right
  /// frame's mask of the designated colours, for the silhouette disparity: the whole frame, or a part of it
  /// at `right_colour_origin` holding at least rightColourRegion(roi). `left_colour` (optional, CV_8UC1 over
  /// leftColourRegion(roi)): the left frame's mask cut as `right_colour` was, read inside `roi` for the left
  /// silhouette instead of `mask` (a candidate's mask is one filled region; the right one is cut pixel by pixel:
  /// alike, the two silhouettes align), and beside it for what touches the object: a right silhouette that runs on
  /// beyond the left one's outline where the left frame shows nothing is no silhouette of it (a nearer object's,
  /// or one that hides part of it from the left camera), and the disparity is searched as without one.
  /// `agreement` (optional: no water to skip; colour frames only): how the object stood out from the water in the
  /// left frame (RoiPoints::unseen_points).
  /// @throw std::invalid_argument on wrong types or sizes, an roi or right_colour outside the image, or an
  /// `agreement` whose water is not BGR8 or whose scale (0, 1], level, spreads or ratio offset (> 0) are out of range.
  RoiPoints match(const RawFrame& left, const RawFrame& right, const cv::Rect& roi, const cv::Mat& mask,
                  const cv::Mat& right_colour = cv::Mat(), const cv::Point& right_colour_origin = cv::Point(),
                  const cv::Mat& left_colour = cv::Mat(), const ViewAgreement& agreement = ViewAgreement()) const;

  /// The part of the raw left frame whose colour mask match() reads beside `roi`: a few columns more on either side.
  cv::Rect leftColourRegion(const cv::Rect& roi) const;

  /// The part of the raw right frame whose colour mask the silhouette disparity of `roi` reads (empty when
  /// the object's right view cannot be in the image).
  cv::Rect rightColourRegion(const cv::Rect& roi) const;

  /// Rectified-frame bounding box of a raw-image rectangle (left camera).
  cv::Rect rectifiedBox(const cv::Rect& raw_roi) const;

  const StereoCalibration& calibration() const { return calibration_; }

  /// [m] The nearest depth matched (nearestMatchedDepthM of this calibration and configuration).
  double nearestDepthM() const;

  /// How the left image's patch over `roi` (raw pixels) matches the right image at the workspace's disparities of
  /// either sign (compareStereoOrder): whether the pair looks swapped there.
  StereoOrder stereoOrder(const RawFrame& left, const RawFrame& right, const cv::Rect& roi) const;

 private:
  /// The sub-pixel disparity of the object's outline: the shift of its rectified column profile in the right colour
  /// mask, compared only as far as the left frame shows the object (one cut by its right edge runs on in the right
  /// frame); NaN when no shift aligns the two, or when the right one runs on where the left frame's mask `around`
  /// (at `around_origin`, over leftColourRegion(roi); empty: not judged) shows nothing. `box`: the object's
  /// rectified box (rectifiedBox(roi)).
  double silhouetteDisparity(const cv::Mat& mask, const cv::Rect& roi, const cv::Mat& right_colour,
                             const cv::Point& right_colour_origin, const cv::Rect& box, const cv::Mat& around = cv::Mat(),
                             const cv::Point& around_origin = cv::Point()) const;
  /// The disparities block matching searches: [min, min + num), num in whole steps of 16.
  struct DisparityWindow {
    int min = 0, num = 0;
  };
  /// The rectified rectangles matched (the right one is the left moved left by min_disparity; either may reach
  /// left of the image, x < 0, where it is padded) and the disparities searched in them.
  struct MatchBand {
    cv::Rect left, right;
    int min_disparity = 0, num_disparities = 0;
  };

  /// @throw std::invalid_argument as match() says.
  void checkMatchInputs(const RawFrame& left, const RawFrame& right, const cv::Rect& roi, const cv::Mat& mask,
                        const cv::Mat& right_colour, const cv::Point& right_colour_origin, const cv::Mat& left_colour) const;
  /// Around a finite disparity (the silhouette's, or the half-size search's) by the expected relief of an
  /// object of rectified box `box`; else the whole workspace.
  DisparityWindow disparityWindow(double silhouette_disparity, const cv::Rect& box) const;
  /// The workspace and beyond its far end, from half that end's disparity (kBeyondFarEndReach), as far as block
  /// matching's budget (kMaxSgbmDisparities) leaves room after the workspace.
  DisparityWindow workspaceAndBeyond() const;
  /// The band around `box` (plus the margin) that `window` needs, clipped to the image's top, bottom and right.
  MatchBand matchBand(const DisparityWindow& window, const cv::Rect& box) const;
  /// The median disparity of the mask's pixels that block matching at half size matches in `band` (whose bands
  /// and mask are given at full size); NaN when fewer than kMinCoarseMatches match, when it lies nearer than the
  /// workspace's near end, or beyond its far end with most matches away from it (beyond the far end where they
  /// agree, it is given: RoiPoints::beyond_far_end).
  double coarseDisparity(const cv::Mat& left_band, const cv::Mat& right_band, const cv::Mat& mask_band,
                         const MatchBand& band) const;
  /// Semi-global block matching of the rectified grey bands: CV_16SC1 disparities in 1/16 px (-16: none).
  cv::Mat blockMatch(const cv::Mat& left_band, const cv::Mat& right_band, int num_disparities) const;
  /// The mask's matched pixels to 3D points in the raw left frame (counts and points into `out`), but those the
  /// raw frames `left` and `right` show in other colours, and none when the right camera does not see the object
  /// (`agreement`: RoiPoints::unseen).
  void reproject(const RawFrame& left, const RawFrame& right, const cv::Mat& mask_band, const cv::Mat& disparity16,
                 const MatchBand& band, const ViewAgreement& agreement, RoiPoints& out) const;
  /// Whether a disparity [px] lies within the workspace's depths (false for NaN).
  bool inWorkspace(double disparity) const;
  /// Disparities [px] of the workspace's far and near ends (the near one at most kMaxSgbmDisparities beyond the far).
  std::pair<int, int> workspaceDisparities() const;
  /// The rectified box the left silhouette is read in, and the rectified columns (same rows) that hold it
  /// and the right silhouette at every workspace disparity (empty if none fits in the image).
  cv::Rect silhouetteBox(const cv::Rect& box) const;
  cv::Rect silhouetteSpan(const cv::Rect& box) const;

  StereoCalibration calibration_;
  StereoMatchConfig config_;
  /// Rectified -> raw pixel, fixed point: CV_16SC2 integer pixel and CV_16UC1 interpolation index.
  cv::Mat left_map_xy_, left_map_fraction_, right_map_xy_, right_map_fraction_;
  cv::Matx33d left_r_transposed_;                                 ///< rectified -> raw left frame
  std::vector<double> left_frame_end_;  ///< per rectified row, the column where the left raw frame's right edge lies
};

/// [m] The nearest depth `calibration` matches with `workspace`: workspace.min_depth_m, or farther when the
/// workspace would span more than kMaxSgbmDisparities disparities (focal length x baseline over 569 px m at
/// 0.5-5 m): its near end is then not searched. workspace.min_depth_m for a calibration whose focal length x
/// baseline is not a head's (not finite, not positive, over 1e6 px m).
double nearestMatchedDepthM(const StereoCalibration& calibration, const StereoMatchConfig& workspace);

}  // namespace underwater_stereo
