// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file One GigE Vision camera through Aravis: open, configure (explicitly, read back), stream into a fixed
/// pool of buffers, hand out frames. ROS-free.

#include <opencv2/core.hpp>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "underwater_stereo/camera/genicam_features.h"
#include "underwater_stereo/camera/stereo_source.h"

namespace underwater_stereo {

enum class TriggerMode { kFreeRun, kSoftware, kHardware };

/// How the stereo head is synchronised: "free_run", "software" or "hardware".
/// @throw std::invalid_argument for any other name.
TriggerMode triggerModeFromName(const std::string& name);

struct CameraSettings {
  std::string id;                       ///< Aravis device id, IP address, serial number or user id
  std::string pixel_format = "BayerRG8";  ///< BayerRG8/BG8/GB8/GR8, Mono8, RGB8Packed
  double frame_rate_hz = 15.0;          ///< free run: the camera's rate; software: the trigger rate
  double exposure_us = 0.0;             ///< > 0: fixed; 0: auto within the limits below
  double exposure_auto_min_us = 100.0;
  double exposure_auto_max_us = 20000.0;
  double gain = -1.0;                   ///< >= 0: fixed (dB, or raw units on cameras with GainRaw only); < 0: auto
  int binning = 1;                      ///< 1, 2, 4
  int roi_x = 0, roi_y = 0, roi_width = 0, roi_height = 0;  ///< 0 width/height: the full sensor
  int packet_size = 1500;               ///< [bytes] GevSCPSPacketSize; 0: negotiate (may exceed the path MTU); 9000 with jumbo frames
  int packet_delay_ns = 0;              ///< inter-packet delay (GevSCPD) for two cameras sharing one link
  bool packet_resend = true;
  int socket_buffer_bytes = 0;          ///< 0: automatic (payload size)
  int buffers = 8;                      ///< fixed pool of stream buffers
  TriggerMode trigger = TriggerMode::kFreeRun;
  std::string trigger_line = "Line1";   ///< hardware mode: the input line (Line0 on the fake camera)
  std::string trigger_activation = "RisingEdge";

  std::vector<std::string> validate(const std::string& name) const;
};

/// A received frame.
struct CameraFrame {
  cv::Mat image;                 ///< a view of `pixels`
  /// The pixels, copied once out of the stream buffer into storage a receiver can take over (a ROS message's
  /// data vector) without a second copy.
  std::shared_ptr<std::vector<std::uint8_t>> pixels;
  std::string encoding;          ///< sensor_msgs encoding: bayer_rggb8, ..., mono8, rgb8
  std::uint64_t device_ns = 0;   ///< the camera's timestamp (0 if it has none)
  std::int64_t host_ns = 0;      ///< host receive time (system clock)
  std::uint32_t frame_id = 0;    ///< GigE Vision block id
  std::int64_t capture_ns = 0;   ///< capture time on the host clock (set by the stereo source, ClockMapper)
  FrameCapture capture;          ///< exposure, gain, ... (set by the stereo source)
};

/// Stream counters (cumulative since opened).
struct CameraStatistics {
  std::uint64_t completed = 0, failed = 0, underruns = 0, missing_packets = 0, resent_packets = 0;
  double temperature_c = std::numeric_limits<double>::quiet_NaN();  ///< NaN when the camera has no sensor
};

/// sensor_msgs encoding of a GenICam pixel format name ("" when the detector cannot take it).
std::string encodingOfPixelFormat(const std::string& pixel_format);

class AravisCamera : public FeatureAccess {
 public:
  /// Opens and configures the camera; values are read back and logged into `report` (one line each). Automatic
  /// exposure or gain on a camera without ExposureAuto or GainAuto leaves its current value (see unsupported()).
  /// @throw std::runtime_error when it cannot be opened or refuses a value (the message says which).
  AravisCamera(const CameraSettings& settings, std::vector<std::string>& report);
  ~AravisCamera() override;
  AravisCamera(const AravisCamera&) = delete;
  AravisCamera& operator=(const AravisCamera&) = delete;

  void start();
  void stop();
  /// The next complete frame within `timeout_ms`; false on timeout. Incomplete or failed buffers are
  /// requeued and counted, never returned.
  bool next(CameraFrame& frame, int timeout_ms);
  /// Fires TriggerSoftware. @throw std::runtime_error when the camera cannot be reached.
  void trigger();
  /// False once Aravis reported the control connection lost.
  bool connected() const;
  CameraStatistics statistics();
  const std::string& description() const { return description_; }
  /// What the settings asked for and the camera lacks, one line each starting with the feature's name (e.g.
  /// "ExposureAuto: ..."); the camera streams with its current value instead. Empty when it has everything.
  const std::vector<std::string>& unsupported() const { return unsupported_; }

  // FeatureAccess over the camera's GenICam nodes.
  bool available(const std::string& name) const override;
  void setFloat(const std::string& name, double value) override;
  double getFloat(const std::string& name) const override;
  void setInteger(const std::string& name, long value) override;
  long getInteger(const std::string& name) const override;
  void setString(const std::string& name, const std::string& value) override;
  std::string getString(const std::string& name) const override;
  void setBoolean(const std::string& name, bool value) override;
  bool getBoolean(const std::string& name) const override;
  void execute(const std::string& name) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string description_;
  std::vector<std::string> unsupported_;
};

}  // namespace underwater_stereo
