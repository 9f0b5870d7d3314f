// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Where stereo pairs come from: a pair of GigE cameras or the simulated scene, behind one interface.

#include <opencv2/core.hpp>

#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "underwater_stereo/common/ground_truth.h"

namespace underwater_stereo {

/// How one camera took one frame (real cameras only).
struct FrameCapture {
  std::string camera;              ///< the camera's description (id, vendor, model, serial)
  std::uint32_t frame_id = 0;      ///< GigE Vision block id
  std::uint64_t device_ns = 0;     ///< the camera's timestamp (PTP time when ptp is true)
  bool ptp = false;                ///< the capture time derives from the cameras' shared PTP clock
  double exposure_us = std::numeric_limits<double>::quiet_NaN();
  double gain = std::numeric_limits<double>::quiet_NaN();  ///< in gain_unit
  std::string gain_unit;           ///< "dB", or "raw" on cameras with GainRaw only
  double temperature_c = std::numeric_limits<double>::quiet_NaN();  ///< NaN: no DeviceTemperature
};

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
  /// Real cameras only: the storage behind `left` and `right` (one copy out of the camera's buffer, into a
  /// PixelBufferPool buffer). The receiver may swap it into its message instead of copying (and back when the
  /// message is done, so the buffer is recycled); `left` and `right` must not be read while it is swapped out.
  std::shared_ptr<std::vector<std::uint8_t>> left_pixels, right_pixels;
  /// Real cameras only: how each frame was taken.
  std::optional<FrameCapture> left_capture, right_capture;
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
