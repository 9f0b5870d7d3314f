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
#include "underwater_stereo/camera/auto_exposure.h"
#include "underwater_stereo/camera/clock_mapper.h"
#include "underwater_stereo/camera/frame_id_tracker.h"
#include "underwater_stereo/camera/frame_pairer.h"
#include "underwater_stereo/camera/pair_delivery.h"
#include "underwater_stereo/camera/stereo_source.h"

namespace underwater_stereo {

/// What can change while the cameras stream (dynamic_reconfigure), for both cameras at once.
struct StereoControls {
  ExposureSync exposure_sync = ExposureSync::kMasterSlave;
  double exposure_us = 0.0;         ///< fixed: the exposure; master_slave: where auto-exposure starts (0: the
                                    ///< geometric mean of its limits); independent: > 0 fixed, 0 each camera's own
  double gain = -1.0;               ///< fixed: the gain (>= 0); master_slave: >= 0 held, < 0 auto in its limits
                                    ///< (dB cameras only); independent: >= 0 fixed, < 0 each camera's own
  AutoExposureSettings auto_exposure;  ///< master_slave's law, limits and metered region; its exposure limits
                                       ///< are also the cameras' own in independent
  double rate_hz = 15.0;            ///< frame rate (free run) or trigger rate (software)
  int packet_delay_ns = 0;          ///< GevSCPD of both cameras

  std::vector<std::string> validate() const;
};

struct AravisStereoConfig {
  CameraSettings left, right;       ///< their trigger, rate, exposure and gain are set from below
  TriggerMode sync = TriggerMode::kSoftware;
  StereoControls controls;
  bool ptp = false;                 ///< IEEE 1588 on both cameras; without it on either: the clock mapping
  double ptp_timeout_s = 10.0;      ///< waiting for Master/Slave after enabling it
  double max_skew_s = 0.0;          ///< pairing tolerance; 0: 1 ms hardware, 5 ms software, half a period free run
  double frame_timeout_s = 2.0;     ///< no frame from a camera for this long: it is reopened
  double max_backoff_s = 5.0;       ///< reopening attempts back off from 0.25 s up to this

  std::vector<std::string> validate() const;
  double effectiveMaxSkewS() const;
};

/// What a camera is doing.
enum class CameraState { kClosed, kOpening, kStreaming, kReconnecting };

/// "closed", "opening", "streaming", "reconnecting": the diagnostics' words.
inline const char* cameraStateName(CameraState state) {
  switch (state) {
    case CameraState::kClosed: return "closed";
    case CameraState::kOpening: return "opening";
    case CameraState::kStreaming: return "streaming";
    case CameraState::kReconnecting: return "reconnecting";
  }
  return "unknown";
}

/// What one camera is doing, for diagnostics.
struct CameraStatus {
  std::string description;          ///< id, vendor, model, serial once opened
  CameraState state = CameraState::kClosed;
  std::string last_error;
  std::uint64_t frames = 0;         ///< complete frames received
  std::uint64_t missed_frames = 0;  ///< from frame-id gaps
  std::uint64_t outages = 0;        ///< times a streaming camera was lost (reopened without a frame: the same one)
  std::vector<std::string> unsupported;  ///< AravisCamera::unsupported() of the open camera
  std::string ptp = "off";          ///< off; its port state (Master, Slave, Listening, ...); or why it is not used
  bool ptp_settled = false;         ///< Master or Slave: its timestamps are PTP time
  Exposure exposure;                ///< in use (read back); gain in gain_unit
  std::string gain_unit;
  CameraStatistics stream;          ///< counters of the current stream
};

struct StereoStatus {
  CameraStatus left, right;
  std::uint64_t pairs = 0;
  std::uint64_t unpaired = 0;       ///< frames dropped without a partner
  std::string last_unpaired;        ///< the last of them: its side and the stamp difference seen; empty if none
  std::uint64_t out_of_order = 0;   ///< pairs dropped: capture time not after the previous pair's
  std::uint64_t overflowed = 0;     ///< pairs dropped: the receiver was still busy with earlier ones
  double last_skew_ms = 0.0;        ///< capture-time difference of the last pair
  bool ptp_stamps = false;          ///< both cameras PTP-settled: pairs stamped from their shared clock
};

/// Runs one thread per camera: opening, reconfiguring after a loss, firing TriggerSoftware on the shared
/// schedule (software sync), receiving. A camera absent at start is waited for; one that vanishes is reopened
/// with back-off and fully reconfigured while the other keeps streaming. Pairs carry the capture time on the
/// host clock. Pairs reach the callback from one delivery thread, in strictly increasing capture time
/// (PairDelivery). Each camera is used by its own thread only (status() reads copies). Messages (settings
/// read back, errors) go to `log`.
///
/// Exposure (StereoControls::exposure_sync): in master_slave the left camera's thread meters each left frame
/// inside auto_roi and asks both cameras for the next exposure and gain; each camera's thread applies it before
/// its next trigger, so with software sync both frames of the next pair carry it (lag: one frame). Every frame
/// carries the exposure and gain it was taken with (FrameCapture): those applied before its capture time (in
/// independent with the camera's own auto functions: read back as the frame arrives).
/// PTP (ptp): enabled on both cameras after opening; once both are Master or Slave their timestamps share one
/// timescale and both map to the host with one offset; a camera without PTP (or not settled within
/// ptp_timeout_s) is reported in its status and the per-camera clock mapping is used.
class AravisStereoSource : public StereoSource {
 public:
  using Log = std::function<void(bool error, const std::string& message)>;
  /// @throw std::invalid_argument when the configuration does not validate.
  AravisStereoSource(const AravisStereoConfig& config, Log log);
  ~AravisStereoSource() override;

  void start(FrameCallback callback) override;
  void stop() override;
  StereoStatus status();

  /// Changes the controls while streaming. A set that does not validate changes nothing: the problems are
  /// returned (empty: accepted). Exposure, gain, limits, rate and packet delay apply without reopening;
  /// switching to or from independent reopens both cameras (their own auto functions are set at opening).
  std::vector<std::string> reconfigure(const StereoControls& controls);
  StereoControls controls() const;

 private:
  struct Side;
  void runCamera(int side);
  /// Applies controls and exposure changed since this side last looked; false: the camera must be reopened.
  bool applyChanges(int side, AravisCamera& camera);
  /// ptp: enables it and waits for a settled port state; records the state (or why not) in the status.
  void startPtp(int side, AravisCamera& camera);
  /// master_slave: meters a left frame and updates the exposure both cameras are to take.
  void meter(const CameraFrame& frame);
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
  mutable std::mutex controls_mutex_;  ///< guards the four below
  StereoControls controls_;
  std::uint64_t controls_generation_ = 1;
  Exposure wanted_;                    ///< master_slave and fixed: both cameras' exposure and gain
  std::uint64_t wanted_generation_ = 1;
};

}  // namespace underwater_stereo
