// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Regions that stand out from the water, at several levels of saliency, each with the numbers a
/// learnt model names its colour from (or rejects it as water, floor, wall...).

#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "underwater_stereo/detection/water_contrast.h"

namespace underwater_stereo {

struct ProposalConfig {
  /// Saliency levels (in the frame's own spreads, WaterContrast) at which regions are cut, low to high: a
  /// faint distant buoy shows at the low ones, a near one separates from the floor at the high ones.
  std::vector<double> levels{8, 16, 32, 64};
  double min_area_px = 12;   ///< searched-image pixels; smaller regions are not proposed
  double max_area_px = 1e6;  ///< larger regions are not proposed
  int max_proposals = 400;   ///< per frame, the most salient kept
  /// Large regions a colour model names are also cut along the image's chromaticity steps (cutIntoPieces): where the
  /// gradient of ln(R / G) and ln(B / G) together exceeds this per searched pixel (0: never). Two touching objects (a
  /// box behind a buoy, a panel against a sphere, a buoy against a distractor) make one region at every saliency
  /// level; its pieces may be named apart, or one named other than the region (findLearnedCandidates). The Detector
  /// cuts none in a dark frame. 0.07 chosen on the validation seeds 60000-60299 among 0.05, 0.07 and 0.1, the one that
  /// leaves the fixed scenes as they were (docs/accuracy.md, "Touching objects cut where their chromaticity steps").
  double piece_step = 0.07;

  std::vector<std::string> validate() const;
};

/// One proposed region, in the searched image's pixels.
struct BlobProposal {
  std::vector<cv::Point> contour;
  cv::Rect roi;
  cv::Mat mask;   ///< CV_8UC1 roi-sized, 255 inside
  double area_px = 0;
  SaliencyKind kind = SaliencyKind::kChroma;  ///< the saliency it was cut from
  double level = 0;                           ///< and at which level
  std::vector<float> features;                ///< kBlobFeatureCount values, blobFeatureNames() order
  bool piece = false;  ///< cut from a larger proposal along the image's steps (cutIntoPieces)
};

/// Number and names of the features of a proposal, in order (stored with a learnt model to check it).
constexpr int kBlobFeatureCount = 36;
const std::vector<std::string>& blobFeatureNames();

/// Regions of `bgr` (the searched image, 8-bit BGR) measured by `contrast` (measureWaterContrast of it), on
/// `threads` threads (workOnThreads; the same regions whatever the number).
/// @throw std::invalid_argument when the sizes differ, the image is not CV_8UC3 or the config is invalid.
std::vector<BlobProposal> proposeBlobs(const cv::Mat& bgr, const WaterContrast& contrast, const ProposalConfig& config,
                                       int threads = 1);

/// The features of `regions`, a row each (CV_32F, kBlobFeatureCount columns): what a colour model classifies.
cv::Mat featureRows(const std::vector<BlobProposal>& regions);

/// A region is cut into pieces from this many times ProposalConfig::min_area_px.
constexpr double kPieceRegionAreas = 8;

/// The pieces (BlobProposal::piece, with their features) that the image's steps (ProposalConfig::piece_step) cut
/// those of `regions` (proposeBlobs' of `bgr` and `contrast`) into that are at least kPieceRegionAreas x min_area_px;
/// each piece once, however many regions it was cut from. None at piece_step 0.
/// @throw std::invalid_argument when the sizes differ or the image is not CV_8UC3.
std::vector<BlobProposal> cutIntoPieces(const cv::Mat& bgr, const WaterContrast& contrast,
                                        const std::vector<const BlobProposal*>& regions, const ProposalConfig& config);

/// The mask (CV_8UC1 0/255, of `contrast`'s size) of the pixels a proposal of this kind and level is cut from.
cv::Mat salientMask(const WaterContrast& contrast, SaliencyKind kind, double level);

/// The part of that mask inside `band` (a rectangle of the frame): equal to the whole mask's part there when the
/// band is salientBand's, which leaves out only rows the mask is empty in.
/// @throw std::invalid_argument when the band is empty or not inside the frame.
cv::Mat salientMask(const WaterContrast& contrast, SaliencyKind kind, double level, const cv::Rect& band);

/// The rows of the frame a cut at `level` can find anything in (those whose largest saliency of this kind
/// exceeds it, with the opening's margin), across the whole width; empty when no row does. The whole frame
/// when `contrast` carries no row maxima. Cutting only there skips 51 % of the rows of the pool scene's frame
/// and 25-30 % of randomised and TRANSDEC frames' rows (averaged over the 8 cuts).
cv::Rect salientBand(const WaterContrast& contrast, SaliencyKind kind, double level);

/// `mask` (CV_8UC1) grown by `radius` pixels in every direction: what cv::dilate with a square of side
/// 2 radius + 1 gives (pixels beyond the edge take no part), without its set-up per call, which was most of
/// its cost on a frame's ~300 small regions (describing a proposal's ring of water).
cv::Mat squareDilation(const cv::Mat& mask, int radius);

}  // namespace underwater_stereo
