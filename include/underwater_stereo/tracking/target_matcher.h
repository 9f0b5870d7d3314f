// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Which configured target a detection is: colour, shape and metric size.

#include <Eigen/Core>

#include <string>

#include "underwater_stereo/tracking/tracking_config.h"

namespace underwater_stereo {

/// What a detection is with respect to the configured targets.
enum class TargetFit {
  kTarget,     ///< fits a target (index given)
  kNoTarget,   ///< no target has its colour and shape: an ordinary detection
  kWrongSize,  ///< a target's colour and shape, but no target's size: a blob to reject
};

struct TargetMatch {
  TargetFit fit = TargetFit::kNoTarget;
  int target = -1;  ///< index into TrackingConfig::targets when fit == kTarget
};

/// Labels detections with the configured targets.
class TargetMatcher {
 public:
  /// @throw std::invalid_argument when the configuration does not validate.
  explicit TargetMatcher(const TrackingConfig& config);

  /// The target a detection of `colour`, `shape` (shapesAgree with the target's: kUnknown fits a target of any
  /// shape) and extents `size_m` (its largest component is compared with Target::size_m) fits best (the smallest
  /// relative size error).
  TargetMatch match(const std::string& colour, ShapeKind shape, const Eigen::Vector3d& size_m) const;

  /// Whether a detection with this match is reported and tracked (targets_only, reject_wrong_size).
  bool keep(const TargetMatch& m) const;

 private:
  TrackingConfig config_;
};

}  // namespace underwater_stereo
