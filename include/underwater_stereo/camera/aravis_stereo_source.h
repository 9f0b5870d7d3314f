// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Two GigE cameras as one stereo source: synchronisation, pairing, reconnection. ROS-free.

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "underwater_stereo/camera/aravis_camera.h"
#include "underwater_stereo/camera/clock_mapper.h"
#include "underwater_stereo/camera/frame_id_tracker.h"
#include "underwater_stereo/camera/frame_pairer.h"
#include "underwater_stereo/camera/pair_delivery.h"
#include "underwater_stereo/camera/stereo_source.h"

namespace underwater_stereo {

struct AravisStereoConfig {
  CameraSettings left, right;       ///< their `trigger` is set from `sync`
  TriggerMode sync = TriggerMode::kSoftware;
  double rate_hz = 15.0;            ///< frame rate (free run) or trigger rate (software)
  double max_skew_s = 0.0;          ///< pairing tolerance; 0: 1 ms hardware, 5 ms software, half a period free run
  double frame_timeout_s = 2.0;     ///< no frame from a camera for this long: it is reopened
  double max_backoff_s = 5.0;       ///< reopening attempts back off from 0.25 s up to this

  std::vector<std::string> validate() const;
  double effectiveMaxSkewS() const;
};

/// What one camera is doing, for diagnostics.
struct CameraStatus {
  std::string description;          ///< id, vendor, model, serial once opened
  std::string state = "closed";     ///< closed, opening, streaming, reconnecting
  std::string last_error;
  std::uint64_t frames = 0;         ///< complete frames received
  std::uint64_t missed_frames = 0;  ///< from frame-id gaps
  std::uint64_t outages = 0;        ///< times the camera was lost and reopened
  std::vector<std::string> unsupported;  ///< AravisCamera::unsupported() of the open camera
  CameraStatistics stream;          ///< counters of the current stream
};

struct StereoStatus {
  CameraStatus left, right;
  std::uint64_t pairs = 0;
  std::uint64_t unpaired = 0;       ///< frames dropped without a partner
  std::uint64_t out_of_order = 0;   ///< pairs dropped: capture time not after the previous pair's
  std::uint64_t overflowed = 0;     ///< pairs dropped: the receiver was still busy with earlier ones
  double last_skew_ms = 0.0;        ///< capture-time difference of the last pair
};

/// Runs one thread per camera: opening, reconfiguring after a loss, firing TriggerSoftware on the shared
/// schedule (software sync), receiving. A camera absent at start is waited for; one that vanishes is reopened
/// with back-off and fully reconfigured while the other keeps streaming. Pairs carry the capture time on the
/// host clock. Pairs reach the callback from one delivery thread, in strictly increasing capture time
/// (PairDelivery). Each camera is used by its own thread only (status() reads copies). Messages (settings
/// read back, errors) go to `log`.
class AravisStereoSource : public StereoSource {
 public:
  using Log = std::function<void(bool error, const std::string& message)>;
  /// @throw std::invalid_argument when the configuration does not validate.
  AravisStereoSource(const AravisStereoConfig& config, Log log);
  ~AravisStereoSource() override;

  void start(FrameCallback callback) override;
  void stop() override;
  StereoStatus status();

 private:
  struct Side;
  void runCamera(int side);
  void deliver(int side, CameraFrame frame, std::int64_t capture_ns);

  AravisStereoConfig config_;
  Log log_;
  std::unique_ptr<Side> sides_[2];
  std::mutex pair_mutex_;  ///< guards pairer_, last_skew_ms_, delivery_ (pushing to it)
  FramePairer<CameraFrame> pairer_;
  double last_skew_ms_ = 0.0;
  std::unique_ptr<PairDelivery> delivery_;  ///< while started
  PairDelivery::Counts delivered_before_;   ///< its counts when stopped
  std::atomic<bool> running_{false};
};

}  // namespace underwater_stereo
