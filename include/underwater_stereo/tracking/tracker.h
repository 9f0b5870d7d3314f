// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Multi-object tracker: a constant-velocity Kalman filter per object, Mahalanobis gating, one-to-one
/// association by increasing cost, tentative and confirmed tracks, out-of-view tracks kept as landmarks.
///
/// Frames: tracks live in one tracking frame (the vehicle's fixed frame, e.g. odom, or the camera's own
/// frame when there is none); observations arrive in the left optical frame with the camera's pose in the
/// tracking frame.

#include <Eigen/Geometry>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "underwater_stereo/detection/shape_kind.h"
#include "underwater_stereo/tracking/constant_velocity_filter.h"
#include "underwater_stereo/tracking/tracking_config.h"

namespace underwater_stereo {

enum class TrackStatus { kTentative, kConfirmed };

/// One tracked object. Positions [m], velocities [m/s], covariances [m^2] in the tracking frame.
struct Track {
  std::uint32_t id = 0;         ///< > 0, never reused by one Tracker
  TrackStatus status = TrackStatus::kTentative;
  std::string colour;
  ShapeKind shape = ShapeKind::kUnknown;  ///< the latest known shape (kUnknown until one is measured)
  int target = -1;              ///< index into TrackingConfig::targets, -1: none
  std::string label;            ///< the target's name, empty when none
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();  ///< mean of the measured sizes
  ConstantVelocityFilter filter;
  std::uint32_t observations = 0;  ///< detections fused
  int misses = 0;               ///< pairs in a row in which it was expected in view (or tentative) and not found
  bool in_view = false;         ///< inside the camera's view at the last pair (found or not)
  /// In view at the last pair but not found, its image within a detection's (occluded, or merged with it by the
  /// detector): not counted as a miss.
  bool hidden = false;
  double first_seen_s = 0.0, last_seen_s = 0.0;  ///< [s] stamps of the first and latest fused detections
};

/// One detection, as the tracker needs it.
struct Observation {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  ///< [m] centre in the left optical frame
  std::string colour;
  ShapeKind shape = ShapeKind::kUnknown;
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();
  int target = -1;              ///< index into TrackingConfig::targets (TargetMatcher), -1: none
  /// Its image touches the image's border: the object is partly out of view and its centre guessed from a
  /// part. It may update a track; it starts none.
  bool cut_by_border = false;
};

/// One stereo pair's detections.
struct TrackingFrame {
  double stamp_s = 0.0;         ///< [s] the pair's stamp
  /// The left optical frame's pose in the tracking frame (identity when tracking in the camera frame).
  Eigen::Isometry3d camera_pose = Eigen::Isometry3d::Identity();
  /// Whether the camera should see a point given in the left optical frame (e.g. CameraView::sees); empty:
  /// every track is expected in view.
  std::function<bool(const Eigen::Vector3d&)> in_view;
  std::vector<Observation> observations;
};

/// What update() did with a frame.
enum class FrameOutcome {
  kTracked,         ///< fused
  kInvalid,         ///< NaN stamp or camera pose: ignored, tracks kept
  kStampBackwards,  ///< earlier than the previous pair by at most max_backwards_s: ignored, tracks kept
  kClockRestarted,  ///< earlier by more than max_backwards_s (a bag restarted): tracks reset, then fused
  kCameraJumped,    ///< the camera moved faster than max_camera_speed_mps or turned faster than
                    ///< max_camera_turn_rate_dps (odometry jumped): tracks reset, then fused
};

/// Name of an outcome for diagnostics ("tracked", "invalid frame", ...).
std::string frameOutcomeName(FrameOutcome outcome);

struct TrackingUpdate {
  FrameOutcome outcome = FrameOutcome::kTracked;
  std::vector<std::uint32_t> track_ids;  ///< per observation: its track's id, 0 when not tracked
  std::vector<std::string> problems;     ///< what was wrong (invalid observations, the outcome's reason)
  std::vector<std::uint32_t> dropped;    ///< tracks removed by this frame (missed, or reset)
};

/// Tracks objects over a sequence of pairs. Not thread-safe: one caller, frames in stamp order.
///
/// Motion: a constant-velocity Kalman filter per track; a track out of view whose velocity is not significantly
/// non-zero (chi-square 95 %) is held in place, its uncertainty growing as if it had moved.
///
/// Association: the squared Mahalanobis distance of every compatible (same colour, same target, same shape
/// unless one is unknown) observation-track pair within the gate; pairs taken greedily, confirmed tracks
/// before tentative ones, then by increasing distance. Greedy rather than Hungarian: a few objects per pair,
/// compatibility classes split them further, and in 3D two same-colour objects whose images cross are
/// still far apart in depth, so gates rarely compete; where they do, the closest pair is the likely one
/// (Hungarian's minimal sum can trade a sure match for two marginal ones).
class Tracker {
 public:
  /// @throw std::invalid_argument when the configuration does not validate.
  explicit Tracker(const TrackingConfig& config);

  TrackingUpdate update(const TrackingFrame& frame);
  /// Removes every track and forgets the previous pair's stamp and pose (ids keep counting up).
  void reset();

  const std::vector<Track>& tracks() const { return tracks_; }
  /// The track with this id, or nullptr.
  const Track* find(std::uint32_t id) const;
  /// The confirmed track labelled `label` seen most recently (most observations on a tie), or nullptr.
  const Track* findConfirmed(const std::string& label) const;
  /// [s] stamp of the latest fused pair; NaN before the first.
  double lastStamp() const { return last_stamp_s_; }

  /// Measurement covariance [m^2] of a detection at `p_camera` (left optical frame), in that frame:
  /// range_sigma along the viewing ray, lateral_sigma across it; both cut_by_border_sigma_scale times larger
  /// for a detection the image border cuts.
  Eigen::Matrix3d measurementCovariance(const Eigen::Vector3d& p_camera, bool cut_by_border = false) const;

 private:
  bool compatible(const Track& t, const Observation& o) const;
  /// Checks stamp and camera pose against the previous pair; resets when they say the world changed.
  FrameOutcome checkFrame(const TrackingFrame& frame, TrackingUpdate& out);

  TrackingConfig config_;
  std::vector<Track> tracks_;
  std::uint32_t next_id_ = 1;
  double last_stamp_s_;
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();
};

}  // namespace underwater_stereo
