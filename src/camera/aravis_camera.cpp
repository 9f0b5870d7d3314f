// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/aravis_camera.h"

#include <arv.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "underwater_stereo/camera/camera_controls.h"
#include "underwater_stereo/camera/pixel_buffer_pool.h"

namespace underwater_stereo {
namespace {

/// Throws std::runtime_error with `what` and the GError's message, freeing it, when `error` is set.
void check(GError* error, const std::string& what) {
  if (!error) return;
  const std::string message = what + ": " + error->message;
  g_error_free(error);
  throw std::runtime_error(message);
}

std::string toString(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

TriggerMode triggerModeFromName(const std::string& name) {
  if (name == "free_run") return TriggerMode::kFreeRun;
  if (name == "software") return TriggerMode::kSoftware;
  if (name == "hardware") return TriggerMode::kHardware;
  throw std::invalid_argument("sync '" + name + "' is not hardware, software or free_run");
}

std::string encodingOfPixelFormat(const std::string& f) {
  if (f == "BayerRG8") return "bayer_rggb8";
  if (f == "BayerBG8") return "bayer_bggr8";
  if (f == "BayerGB8") return "bayer_gbrg8";
  if (f == "BayerGR8") return "bayer_grbg8";
  if (f == "Mono8") return "mono8";
  if (f == "RGB8" || f == "RGB8Packed") return "rgb8";
  return "";
}

std::vector<std::string> CameraSettings::validate(const std::string& name) const {
  std::vector<std::string> p;
  if (id.empty()) p.push_back(name + ".id: empty (device id, IP address, serial number or user id)");
  if (encodingOfPixelFormat(pixel_format).empty()) {
    p.push_back(name + ".pixel_format: '" + pixel_format + "' is not BayerRG8/BG8/GB8/GR8, Mono8 or RGB8Packed");
  }
  if (!(frame_rate_hz > 0 && frame_rate_hz <= 200)) p.push_back(name + ".frame_rate_hz must be in (0, 200]");
  if (exposure_us < 0) p.push_back(name + ".exposure_us must be >= 0 (0: auto)");
  if (!(exposure_auto_min_us > 0 && exposure_auto_min_us < exposure_auto_max_us)) {
    p.push_back(name + ": need 0 < exposure_auto_min_us < exposure_auto_max_us");
  }
  if (binning != 1 && binning != 2 && binning != 4) p.push_back(name + ".binning must be 1, 2 or 4");
  if (roi_x < 0 || roi_y < 0 || roi_width < 0 || roi_height < 0) p.push_back(name + ": ROI values must be >= 0");
  if (packet_size != 0 && (packet_size < 576 || packet_size > 9000)) {
    p.push_back(name + ".packet_size must be 0 (negotiate) or in [576, 9000]");
  }
  if (packet_delay_ns < 0) p.push_back(name + ".packet_delay_ns must be >= 0");
  if (socket_buffer_bytes < 0) p.push_back(name + ".socket_buffer_bytes must be >= 0");
  if (buffers < 2 || buffers > 64) p.push_back(name + ".buffers must be in [2, 64]");
  return p;
}

struct AravisCamera::Impl {
  ArvCamera* camera = nullptr;
  ArvDevice* device = nullptr;
  ArvStream* stream = nullptr;
  gulong lost_handler = 0;
  std::atomic<bool> lost{false};
  std::string encoding;
  bool acquiring = false;
  /// The stream buffers' memory, from the frame pool (Aravis does not free preallocated data); released after
  /// the stream is unreferenced, in the destructor's body, so a camera loaded again reuses it.
  std::vector<PixelBufferPool::Buffer> stream_storage;

  static void onControlLost(ArvDevice*, gpointer self) { static_cast<Impl*>(self)->lost = true; }

  ~Impl() {
    if (camera && acquiring) arv_camera_stop_acquisition(camera, nullptr);
    if (device && lost_handler) g_signal_handler_disconnect(device, lost_handler);
    if (stream) g_object_unref(stream);
    if (camera) g_object_unref(camera);
  }
};

AravisCamera::AravisCamera(const CameraSettings& s, std::vector<std::string>& report) : impl_(std::make_unique<Impl>()) {
  const auto problems = s.validate("camera");
  if (!problems.empty()) throw std::runtime_error("invalid camera settings: " + problems.front());
  GError* error = nullptr;
  impl_->camera = arv_camera_new(s.id.c_str(), &error);
  check(error, "cannot open camera '" + s.id + "'");
  if (!impl_->camera) throw std::runtime_error("cannot open camera '" + s.id + "': not found");
  impl_->device = arv_camera_get_device(impl_->camera);
  impl_->lost_handler = g_signal_connect(impl_->device, "control-lost", G_CALLBACK(&Impl::onControlLost), impl_.get());
  const char* vendor = arv_camera_get_vendor_name(impl_->camera, nullptr);
  const char* model = arv_camera_get_model_name(impl_->camera, nullptr);
  const char* serial = arv_camera_get_device_serial_number(impl_->camera, nullptr);
  description_ = s.id + " (" + (vendor ? vendor : "?") + " " + (model ? model : "?") + ", serial " +
                 (serial ? serial : "?") + ")";
  report.push_back(description_ + ": opened");
  if (available("AcquisitionStop")) execute("AcquisitionStop");

  setStringFeature(*this, "PixelFormat", s.pixel_format);
  impl_->encoding = encodingOfPixelFormat(s.pixel_format);
  if (s.binning > 1) {
    setInteger("BinningHorizontal", s.binning);
    setInteger("BinningVertical", s.binning);
  }
  if (s.roi_width > 0 && s.roi_height > 0) {
    arv_camera_set_region(impl_->camera, s.roi_x, s.roi_y, s.roi_width, s.roi_height, &error);
    check(error, "the camera refused the ROI");
  }
  gint x = 0, y = 0, w = 0, h = 0;
  arv_camera_get_region(impl_->camera, &x, &y, &w, &h, &error);
  check(error, "cannot read the region");
  report.push_back("PixelFormat " + s.pixel_format + ", region " + std::to_string(w) + "x" + std::to_string(h) + "+" +
                   std::to_string(x) + "+" + std::to_string(y) + ", binning " + std::to_string(s.binning));

  if (arv_camera_is_gv_device(impl_->camera)) {
    if (s.packet_size > 0) {
      arv_camera_gv_set_packet_size(impl_->camera, s.packet_size, &error);
      check(error, "the camera refused packet size " + std::to_string(s.packet_size));
    } else {
      arv_camera_gv_auto_packet_size(impl_->camera, &error);
      check(error, "packet size negotiation failed");
    }
    if (s.packet_delay_ns > 0) {
      arv_camera_gv_set_packet_delay(impl_->camera, s.packet_delay_ns, &error);
      check(error, "the camera refused inter-packet delay " + std::to_string(s.packet_delay_ns) + " ns");
    }
    report.push_back("packet size " + std::to_string(arv_camera_gv_get_packet_size(impl_->camera, nullptr)) +
                     " bytes, inter-packet delay " + std::to_string(arv_camera_gv_get_packet_delay(impl_->camera, nullptr)) +
                     " ns");
  }

  // Trigger: selector, mode, source, activation, explicitly and in this order (Aravis' convenience setters
  // change other features as a side effect).
  if (available("TriggerSelector")) setStringFeature(*this, "TriggerSelector", "FrameStart");
  if (s.trigger == TriggerMode::kFreeRun) {
    if (available("TriggerMode")) setStringFeature(*this, "TriggerMode", "Off");
  } else {
    setStringFeature(*this, "TriggerMode", "On");
    setStringFeature(*this, "TriggerSource", s.trigger == TriggerMode::kSoftware ? "Software" : s.trigger_line);
    if (s.trigger == TriggerMode::kHardware && available("TriggerActivation")) {
      setStringFeature(*this, "TriggerActivation", s.trigger_activation);
    }
  }
  report.push_back("TriggerMode " + (available("TriggerMode") ? getString("TriggerMode") : std::string("-")) +
                   ", TriggerSource " + (available("TriggerSource") ? getString("TriggerSource") : std::string("-")));
  if (s.trigger == TriggerMode::kFreeRun) {
    if (available("AcquisitionFrameRateEnable")) {
      arv_device_set_boolean_feature_value(impl_->device, "AcquisitionFrameRateEnable", TRUE, &error);
      check(error, "cannot enable AcquisitionFrameRate");
    }
    const double rate = setFloatFeature(*this, {"AcquisitionFrameRate", "AcquisitionFrameRateAbs"}, s.frame_rate_hz);
    report.push_back("frame rate " + toString(rate) + " Hz");
  } else if (available("AcquisitionFrameRateEnable")) {
    // Triggered: the trigger sets the rate; a frame-rate limit would drop triggers.
    arv_device_set_boolean_feature_value(impl_->device, "AcquisitionFrameRateEnable", FALSE, &error);
    check(error, "cannot disable AcquisitionFrameRate");
  }
  if (s.exposure_us > 0) {
    report.push_back("exposure " + toString(setExposureUs(*this, s.exposure_us)) + " us (fixed)");
  } else if (!available("ExposureAuto")) {
    // A camera without the feature still streams, at its current value; a value it rejects is still refused.
    unsupported_.push_back("ExposureAuto: the camera has none, so it streams at its current exposure " +
                           toString(exposureUs(*this)) +
                           " us (exposure_us > 0 sets one)");
    report.push_back(unsupported_.back());
  } else {
    setStringFeature(*this, "ExposureAuto", "Continuous");
    for (const auto& [names, value] : {std::make_pair(std::vector<std::string>{"AutoExposureTimeLowerLimit",
                                                                               "AutoExposureTimeAbsLowerLimit"},
                                                      s.exposure_auto_min_us),
                                       std::make_pair(std::vector<std::string>{"AutoExposureTimeUpperLimit",
                                                                               "AutoExposureTimeAbsUpperLimit"},
                                                      s.exposure_auto_max_us)}) {
      if (available(names[0]) || available(names[1])) setFloatFeature(*this, names, value);
    }
    report.push_back("exposure auto in [" + toString(s.exposure_auto_min_us) + ", " + toString(s.exposure_auto_max_us) +
                     "] us");
  }
  if (s.gain >= 0) {
    report.push_back("gain " + toString(setGain(*this, s.gain)) + (gainInDb(*this) ? " dB" : " (raw)") + " (fixed)");
  } else if (!available("GainAuto")) {
    unsupported_.push_back("GainAuto: the camera has none, so it streams at its current gain " +
                           toString(gain(*this)) + (gainInDb(*this) ? " dB" : " (raw)") +
                           " (gain >= 0 sets one)");
    report.push_back(unsupported_.back());
  } else {
    setStringFeature(*this, "GainAuto", "Continuous");
    report.push_back("gain auto");
  }

  impl_->stream = arv_camera_create_stream(impl_->camera, nullptr, nullptr, &error);
  check(error, "cannot create the stream of '" + s.id + "'");
  if (ARV_IS_GV_STREAM(impl_->stream)) {
    g_object_set(impl_->stream, "packet-resend",
                 s.packet_resend ? ARV_GV_STREAM_PACKET_RESEND_ALWAYS : ARV_GV_STREAM_PACKET_RESEND_NEVER, nullptr);
    if (s.socket_buffer_bytes > 0) {
      g_object_set(impl_->stream, "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_FIXED, "socket-buffer-size",
                   s.socket_buffer_bytes, nullptr);
    }
  }
  const guint payload = arv_camera_get_payload(impl_->camera, &error);
  check(error, "cannot read the payload size");
  for (int i = 0; i < s.buffers; ++i) {
    impl_->stream_storage.push_back(PixelBufferPool::frames().acquire(payload));
    arv_stream_push_buffer(impl_->stream, arv_buffer_new(payload, impl_->stream_storage.back()->data()));
  }
  report.push_back(std::to_string(s.buffers) + " stream buffers of " + std::to_string(payload) + " bytes, packet resend " +
                   (s.packet_resend ? "on" : "off"));
}

AravisCamera::~AravisCamera() = default;

void AravisCamera::start() {
  GError* error = nullptr;
  arv_camera_start_acquisition(impl_->camera, &error);
  check(error, "cannot start acquisition on " + description_);
  impl_->acquiring = true;
}

void AravisCamera::stop() {
  if (!impl_->acquiring) return;
  impl_->acquiring = false;
  GError* error = nullptr;
  arv_camera_stop_acquisition(impl_->camera, &error);
  check(error, "cannot stop acquisition on " + description_);
}

bool AravisCamera::next(CameraFrame& frame, int timeout_ms) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::microseconds>(end - std::chrono::steady_clock::now());
    if (left.count() <= 0) return false;
    ArvBuffer* buffer = arv_stream_timeout_pop_buffer(impl_->stream, static_cast<guint64>(left.count()));
    if (!buffer) return false;
    if (arv_buffer_get_status(buffer) != ARV_BUFFER_STATUS_SUCCESS) {  // incomplete, lost packets...
      arv_stream_push_buffer(impl_->stream, buffer);                   // counted by the stream statistics
      continue;
    }
    const int width = arv_buffer_get_image_width(buffer), height = arv_buffer_get_image_height(buffer);
    size_t size = 0;
    const void* data = arv_buffer_get_image_data(buffer, &size);
    const int type = impl_->encoding == "rgb8" ? CV_8UC3 : CV_8UC1;
    if (width <= 0 || height <= 0 || size < static_cast<size_t>(width) * height * CV_ELEM_SIZE(type)) {
      arv_stream_push_buffer(impl_->stream, buffer);
      continue;
    }
    // The one copy of the frame: into a recycled buffer (not zero-filled first) that can become the published
    // message's data.
    auto pixels = PixelBufferPool::frames().acquire(static_cast<std::size_t>(width) * height * CV_ELEM_SIZE(type));
    std::memcpy(pixels->data(), data, pixels->size());
    frame.image = cv::Mat(height, width, type, pixels->data());
    frame.pixels = std::move(pixels);
    frame.encoding = impl_->encoding;
    frame.device_ns = arv_buffer_get_timestamp(buffer);
    frame.host_ns = static_cast<std::int64_t>(arv_buffer_get_system_timestamp(buffer));
    frame.frame_id = static_cast<std::uint32_t>(arv_buffer_get_frame_id(buffer));
    arv_stream_push_buffer(impl_->stream, buffer);
    return true;
  }
}

void AravisCamera::trigger() { execute("TriggerSoftware"); }

bool AravisCamera::connected() const { return !impl_->lost; }

CameraStatistics AravisCamera::statistics() {
  CameraStatistics s;
  guint64 completed = 0, failed = 0, underruns = 0;
  arv_stream_get_statistics(impl_->stream, &completed, &failed, &underruns);
  s.completed = completed;
  s.failed = failed;
  s.underruns = underruns;
  if (ARV_IS_GV_STREAM(impl_->stream)) {
    s.missing_packets = arv_stream_get_info_uint64_by_name(impl_->stream, "n_missing_packets");
    s.resent_packets = arv_stream_get_info_uint64_by_name(impl_->stream, "n_resent_packets");
  }
  if (available("DeviceTemperature")) {
    try {
      s.temperature_c = getFloat("DeviceTemperature");
    } catch (const std::runtime_error&) {
    }
  }
  return s;
}

bool AravisCamera::available(const std::string& name) const {
  GError* error = nullptr;
  const gboolean yes = arv_device_is_feature_available(impl_->device, name.c_str(), &error);
  if (error) {
    g_error_free(error);
    return false;
  }
  return yes;
}

void AravisCamera::setFloat(const std::string& name, double value) {
  GError* error = nullptr;
  arv_device_set_float_feature_value(impl_->device, name.c_str(), value, &error);
  check(error, name);
}

double AravisCamera::getFloat(const std::string& name) const {
  GError* error = nullptr;
  const double v = arv_device_get_float_feature_value(impl_->device, name.c_str(), &error);
  check(error, name);
  return v;
}

void AravisCamera::setInteger(const std::string& name, long value) {
  GError* error = nullptr;
  arv_device_set_integer_feature_value(impl_->device, name.c_str(), value, &error);
  check(error, name);
}

long AravisCamera::getInteger(const std::string& name) const {
  GError* error = nullptr;
  const gint64 v = arv_device_get_integer_feature_value(impl_->device, name.c_str(), &error);
  check(error, name);
  return static_cast<long>(v);
}

void AravisCamera::setString(const std::string& name, const std::string& value) {
  GError* error = nullptr;
  arv_device_set_string_feature_value(impl_->device, name.c_str(), value.c_str(), &error);
  check(error, name);
}

std::string AravisCamera::getString(const std::string& name) const {
  GError* error = nullptr;
  const char* v = arv_device_get_string_feature_value(impl_->device, name.c_str(), &error);
  check(error, name);
  return v ? v : "";
}

void AravisCamera::setBoolean(const std::string& name, bool value) {
  GError* error = nullptr;
  arv_device_set_boolean_feature_value(impl_->device, name.c_str(), value ? TRUE : FALSE, &error);
  check(error, name);
}

bool AravisCamera::getBoolean(const std::string& name) const {
  GError* error = nullptr;
  const gboolean v = arv_device_get_boolean_feature_value(impl_->device, name.c_str(), &error);
  check(error, name);
  return v;
}

void AravisCamera::execute(const std::string& name) {
  GError* error = nullptr;
  arv_device_execute_command(impl_->device, name.c_str(), &error);
  check(error, name);
}

}  // namespace underwater_stereo
