// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Step 3 of the pipeline: 2D regions of interest that carry a designated colour.

#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "underwater_stereo/detection/colour_segmenter.h"
#include "underwater_stereo/detection/outline_kind.h"
#include "underwater_stereo/detection/water_contrast.h"

namespace underwater_stereo {

enum class ContourSource {
  kColourMask,     ///< contours of each colour mask (default: edges follow the colour)
  kGreyThreshold,  ///< the paper: grey, Gaussian blur, threshold, contours kept if they carry the colour
  kLearned,        ///< regions standing out from the water, named by a learnt model (learned_candidates.h)
};

enum class ThresholdMode { kOtsu, kFixed };

struct CandidateConfig {
  ContourSource source = ContourSource::kColourMask;
  ThresholdMode threshold = ThresholdMode::kOtsu;  ///< kGreyThreshold only
  int fixed_threshold = 100;                       ///< grey level for ThresholdMode::kFixed
  bool dark_objects = true;                        ///< objects darker than the water (inverted threshold)
  int blur_kernel_px = 5;                          ///< Gaussian blur before thresholding (odd)
  double min_area_px = 400.0;                      ///< smaller contours are ignored
  double max_area_px = 1.0e6;                      ///< larger contours are ignored
  double min_colour_fraction = 0.5;                ///< share of a contour's pixels in one colour mask
  int max_candidates = 20;                         ///< the largest ones are kept

  std::vector<std::string> validate() const;
};

/// One 2D region of interest.
struct Candidate {
  int colour_index = -1;            ///< index into ColourMaskConfig::classes
  std::vector<cv::Point> contour;   ///< outer contour, image pixels
  cv::Rect roi;                     ///< bounding box of the contour
  cv::Mat mask;                     ///< CV_8UC1 roi-sized: the object's pixels (contour filled AND colour)
  double area_px = 0.0;             ///< contour area
  double colour_fraction = 0.0;     ///< share of the contour's pixels in the colour mask
  OutlineKind outline = OutlineKind::kPolygon;  ///< classifyOutline(contour)
  cv::Scalar mean_bgr;              ///< mean colour of the object's pixels in the searched image
  /// How clearly the object's brightness falls into two flat levels: the Fisher ratio (m1 - m2)^2 /
  /// (s1^2 + s2^2) of an Otsu split of its (blurred) grey levels. A box shows faces of flat, different
  /// shading (tens to hundreds); a sphere or cylinder a smooth gradient and a panel one level (a few).
  double face_contrast = 0.0;
  /// kLearned only: the saliency and level the region was cut at (the right frame is cut alike).
  SaliencyKind saliency_kind = SaliencyKind::kChroma;
  double saliency_level = 0.0;
  /// kLearned only: cut from a region that held two objects (or, in 3D, one object cut in two, which the detector
  /// then measures whole), along the image's steps (BlobProposal::piece); part of its outline may be the edge of the
  /// object it touched.
  bool piece = false;
  /// kLearned only, in 3D: a piece standing in place of a region of its own colour (OneColourPieces::kPiecesStand),
  /// there only for stereo to tell two touching objects apart. Its colour is the region's, named from all of the
  /// region's pixels: the check after stereo, reading the piece's fewer pixels and its edge, does not rename it.
  bool colour_of_its_region = false;
  /// kLearned only: its proposal's features and the colour model's shares of votes (what the check after stereo
  /// reads, detection_check.h).
  std::vector<float> colour_features;
};

/// Fisher ratio of an Otsu split of the grey levels of `bgr_roi` under `mask` (Candidate::face_contrast).
double faceContrast(const cv::Mat& bgr_roi, const cv::Mat& mask);

/// Classifies a closed contour: circle, ellipse, triangle, rectangle or (none of those) polygon.
/// @throw std::invalid_argument with fewer than 3 points.
OutlineKind classifyOutline(const std::vector<cv::Point>& contour);

/// The inside of `contour` (image coordinates) filled, over `box` (CV_8UC1 0/255 of its size; 8-connected edge).
cv::Mat filledOutline(const std::vector<cv::Point>& contour, const cv::Rect& box);

/// The outer outline of `mask`'s (CV_8UC1) largest region by area, in image coordinates (`mask` lies at `origin`);
/// empty when there is none or that largest one has fewer than 3 points.
std::vector<cv::Point> largestOutline(const cv::Mat& mask, const cv::Point& origin);

/// True when the hue ranges of two colour classes touch or overlap (within 2 hue units, through 0 too; either may lie
/// inside the other).
bool hueNeighbours(const ColourClass& a, const ColourClass& b);

/// Candidates in `bgr` (the searched image) given its colour masks (from colourMasks() with `classes`),
/// largest first. In kColourMask mode a region of masks.any is one object,
/// labelled with the class holding most of its pixels, when its classes are hue neighbours (shading moves a
/// yellow ball's lower half into orange); classes that are not neighbours of it become candidates of their own.
/// In kGreyThreshold mode the colour share of a contour is counted in the raw class masks.
/// @throw std::invalid_argument when bgr is not CV_8UC3, masks do not match it or not one mask per class.
std::vector<Candidate> findCandidates(const cv::Mat& bgr, const ColourMasks& masks,
                                      const std::vector<ColourClass>& classes, const CandidateConfig& config);

}  // namespace underwater_stereo
