// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Where stereo pairs come from: a pair of GigE cameras or the simulated scene, behind one interface.

#include <opencv2/core.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "underwater_stereo/sim/ground_truth.h"

namespace underwater_stereo {

/// One synchronised stereo pair. Images share one capture instant.
struct StereoFrame {
  cv::Mat left;                 ///< raw image, layout given by encoding
  cv::Mat right;
  std::string encoding;         ///< sensor_msgs/image_encodings name: bayer_rggb8, bgr8, rgb8, mono8
  std::uint64_t sequence = 0;   ///< counts pairs delivered by this source, from 0
  /// Capture time on the host's system clock [ns since the epoch]; 0: not known (the receiver stamps it).
  std::int64_t capture_time_ns = 0;
  /// Truth about the scene; filled by the simulated source only (empty from real cameras).
  std::vector<sim::GroundTruthObject> ground_truth;
  /// The simulated source only: the left optical frame's true pose in the scene's world frame.
  std::optional<Eigen::Isometry3d> camera_pose_world;
};

/// A source of stereo pairs that pushes them to a callback from its own thread.
class StereoSource {
 public:
  using FrameCallback = std::function<void(const StereoFrame&)>;
  virtual ~StereoSource() = default;
  /// Starts delivering pairs to `callback` from a thread of the source's own.
  virtual void start(FrameCallback callback) = 0;
  /// Stops delivering and joins the thread; no callback runs after stop() returns.
  virtual void stop() = 0;
};

}  // namespace underwater_stereo
