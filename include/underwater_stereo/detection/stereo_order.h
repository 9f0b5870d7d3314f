// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Whether a stereo pair came in the wrong order (left and right images swapped): in a right image an object lies
// left of where the left image shows it (positive disparity); in a swapped pair it lies right of it, and without
// this check block matching would measure it at a confident, wrong range.
#include <opencv2/core.hpp>

#include <atomic>
#include <cstddef>
#include <vector>

#include "underwater_stereo/detection/raw_frame.h"

namespace underwater_stereo {

/// How well an object's patch of the left image matches the right image shifted each way.
struct StereoOrder {
  /// A side that was not compared (outside the correlation's range -1..1).
  static constexpr double kNotCompared = -2;
  /// Best normalised cross-correlation (-1..1) over the workspace's disparities: `forward` where the right view
  /// lies left of the left one (as it should), `backward` where it lies right of it (as in a swapped pair).
  double forward = kNotCompared, backward = kNotCompared;
  /// Where `forward` could not be compared (an object at the left border: in a pair in order its view lies beyond
  /// the right image), the patch against the left image itself at the backward shifts: how well a smooth patch
  /// matches itself a little shifted, which a backward match must beat instead.
  double backward_in_left = kNotCompared;
  /// The backward match is plain and clearly better than any forward one (or, without a forward side, than the
  /// patch's match with its own image: a large plain box cut by the left border took its pair for swapped,
  /// docs/reliability.md).
  bool looksSwapped() const;
};

/// Compares the left image's patch over `roi` (raw pixels) with the right image where an object's view lies in a
/// pair in order, [min_shift, max_shift] raw columns left of the patch and `row_offset_px` raw rows lower (from the
/// calibration at the workspace's far and near ends: cameras are never exactly aligned), and where it lies in a
/// swapped pair, as far right and as far higher; on unrectified grey images scaled so that the patch is at most
/// 64 px across. Rows whose view would lie above or below the right image (the row offset) are left out of the
/// compared patch on both sides; shifts the image cannot hold on one side are not compared there (that side stays
/// StereoOrder::kNotCompared), nor is a region too thin to keep 4 pixels across. @throw std::invalid_argument when
/// the frames differ in size, `roi` is not inside them or the offset is not finite.
StereoOrder compareStereoOrder(const RawFrame& left, const RawFrame& right, const cv::Rect& roi, int min_shift,
                               int max_shift, double row_offset_px);

/// What one measured object says about its pair's order.
struct ObjectOrderEvidence {
  bool silhouette = false;  ///< its silhouette was found in the right image at a disparity of the workspace
  StereoOrder order;        ///< compared only where no silhouette was found
};

/// What a pair's measured objects say about its order.
struct PairOrder {
  std::size_t objects = 0;      ///< objects measured
  std::size_t swapped = 0;      ///< of those without a silhouette, those that look swapped
  std::size_t silhouettes = 0;  ///< those that found their silhouette where it should be
  /// At least half of the objects (and at least one) look swapped, and no fewer of them than found their
  /// silhouette (in a swapped pair a silhouette is now and then found in the wrong place, on a neighbour). A lone
  /// object that looks swapped decides its pair; on the validation seeds no pair in order had one
  /// (docs/reliability.md, "A pair in the wrong order").
  bool looksSwapped() const;
};

PairOrder pairOrder(const std::vector<ObjectOrderEvidence>& objects);

/// A stream of pairs' verdicts (Detector::detect's looks_swapped, and whether objects were reported): one pair now and
/// then that looks swapped is a scene that fooled the check (1 of 500 randomised pairs); several with no pair of
/// objects between them are a head wired the wrong way round. Thread-safe (a detector's workers share one).
class SwappedPairWatch {
 public:
  /// Pairs that look swapped, none with objects between them, that make the head's wiring the likely cause.
  static constexpr int kPairsForWiring = 3;
  /// Counts one pair: @return the pairs that looked swapped since the last with objects, when they reach
  /// kPairsForWiring (this pair's included), else 0.
  int add(bool looks_swapped, bool has_objects);

 private:
  std::atomic<int> since_objects_{0};
};

}  // namespace underwater_stereo
