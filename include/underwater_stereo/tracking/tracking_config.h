// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Configuration of the tracker and the list of designated targets, as config/tracking.yaml holds it.

#include <string>
#include <vector>

#include "underwater_stereo/detection/shape_kind.h"

namespace YAML {
class Node;
}

namespace underwater_stereo {

/// An object the mission looks for. A detection fits it when colour and shape agree and its size (largest
/// extent) is within size_tolerance of size_m.
struct Target {
  std::string name;             ///< e.g. "red_buoy"; becomes the detection's and the track's label
  std::string colour;           ///< designated colour class, e.g. "red"
  ShapeKind shape = ShapeKind::kUnknown;  ///< kUnknown: any shape (YAML: left out, empty or "unknown")
  double size_m = 0.0;          ///< [m] largest extent (a sphere's diameter, a cylinder's length)
  double size_tolerance = 0.3;  ///< relative: sizes within size_m * (1 +- size_tolerance) fit
};

/// Tracker parameters. Frames: the tracking frame is the fixed frame (e.g. odom), or the stereo frame.
struct TrackingConfig {
  std::vector<Target> targets;
  bool targets_only = false;       ///< report and track only detections that fit a target
  bool reject_wrong_size = true;   ///< a detection of a target's colour and shape but no target's size is dropped
  bool match_shape = true;         ///< a track takes only detections of its shape (unknown fits any shape)

  // Measurement noise of a detection (stereo): standard deviations grow with range.
  double range_sigma_fraction = 0.008;    ///< along the viewing ray, fraction of the range
  double lateral_sigma_fraction = 0.003;  ///< across the ray, fraction of the range
  double min_sigma_m = 0.005;             ///< [m] added to both
  /// Both standard deviations of a detection cut by the image border (partly out of view, its centre guessed
  /// from a part) times this. 6: on the randomised validation scenes (seeds 60000-60299, docs/accuracy.md) the
  /// median range error of such detections is 5.8 times that of whole ones (3.10 % against 0.53 %).
  double cut_by_border_sigma_scale = 6.0;

  // Motion model: constant velocity driven by white acceleration noise.
  /// [m/s^2] how fast a track's velocity may change (slowly: out of view, position uncertainty grows as dt^3)
  double acceleration_sigma_mps2 = 0.01;
  double initial_speed_sigma_mps = 0.3;   ///< [m/s] velocity uncertainty of a new track (per axis)

  double gate_chi2 = 16.27;   ///< squared Mahalanobis distance beyond which a detection cannot join a track (3 dof, 99.9 %)
  int confirm_hits = 3;       ///< observations that make a tentative track confirmed
  int tentative_max_misses = 2;  ///< a tentative track missed this many pairs in a row is dropped
  int max_misses = 15;        ///< a confirmed track missed this many pairs in a row while in view is dropped
  double view_margin_px = 40.0;  ///< a track is expected in view when it projects this far inside the image
  /// [m] a detection whose image comes this close to a nearer detection's (at the nearer one's range) is not
  /// used: in one of the two cameras the nearer object hides part of it, and its depth is wrong (about the
  /// stereo baseline); nor is the nearer of two of one colour that close (they may make one silhouette in a camera)
  double occlusion_margin_m = 0.1;

  // Bad input.
  double max_camera_speed_mps = 3.0;       ///< [m/s] faster camera motion between pairs is a jump (tracks reset)
  double max_camera_turn_rate_dps = 180.0; ///< [deg/s] faster turns are a jump (tracks reset)
  double max_backwards_s = 1.0;            ///< [s] a stamp further back than this resets the tracks (a restarted clock)

  /// Every problem, each naming its field.
  std::vector<std::string> validate() const;
  /// The target called `name`, or nullptr.
  const Target* target(const std::string& name) const;
};

/// Parses `tracking:` and `targets:` sections (keys as in config/tracking.yaml; missing keys keep defaults).
/// @throw std::invalid_argument listing every problem (unknown keys, wrong types, invalid values).
TrackingConfig parseTrackingConfig(const YAML::Node& root);
/// @throw std::invalid_argument when the file cannot be read or is invalid.
TrackingConfig loadTrackingConfigFile(const std::string& path);

}  // namespace underwater_stereo
