// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/aravis_stereo_source.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "underwater_stereo/camera/camera_controls.h"
#include "underwater_stereo/camera/trigger_schedule.h"
#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {

namespace {
/// Pairs waiting for a slow callback before the oldest is dropped.
constexpr std::size_t kMaxQueuedPairs = 4;
/// The camera thread refreshes its stream statistics (a GVCP read) this often.
constexpr std::chrono::milliseconds kStatisticsPeriod(1000);
}  // namespace

struct AravisStereoSource::Side {
  CameraSettings settings;                ///< as configured; exposure, gain, rate from the controls at opening
  std::mutex mutex;                       ///< guards status and clock (the camera is used by its thread only)
  ClockMapper clock;
  FrameIdTracker ids;
  CameraStatus status;
  std::thread thread;
  // Used by the side's thread only:
  StereoControls in_use;                  ///< the controls applied to the open camera
  std::uint64_t seen_controls = 0, seen_wanted = 0;
  Exposure applied, previous;             ///< read back; previous: before applied_ns
  std::int64_t applied_ns = 0;            ///< host time the last change was sent
  std::atomic<bool> gain_db{false};      ///< read by the other side's thread (master_slave)
  bool camera_auto = false;               ///< independent with the camera's own ExposureAuto/GainAuto running
};

namespace {
std::int64_t hostNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

bool sameExposure(const Exposure& a, const Exposure& b) {
  return std::abs(a.exposure_us - b.exposure_us) <= 0.005 * b.exposure_us && std::abs(a.gain_db - b.gain_db) < 0.01;
}

/// Where master_slave and fixed start: fixed at the controls' values; auto from exposure_us (0: the geometric
/// mean of the limits) and the gain (< 0: its lower limit).
Exposure startExposure(const StereoControls& c) {
  const AutoExposureSettings& a = c.auto_exposure;
  return {c.exposure_us > 0 ? c.exposure_us : std::sqrt(a.exposure_min_us * a.exposure_max_us),
          c.gain >= 0 ? c.gain : a.gain_min_db};
}
}  // namespace

std::vector<std::string> StereoControls::validate() const {
  std::vector<std::string> p = auto_exposure.validate("");
  if (!(rate_hz > 0 && rate_hz <= 200)) p.push_back("rate_hz must be in (0, 200]");
  if (packet_delay_ns < 0) p.push_back("packet_delay_ns must be >= 0");
  if (!(exposure_us >= 0)) p.push_back("exposure_us must be >= 0");
  if (exposure_sync == ExposureSync::kFixed && !(exposure_us > 0 && gain >= 0)) {
    p.push_back("exposure_sync fixed needs exposure_us > 0 and gain >= 0");
  }
  if (exposure_sync == ExposureSync::kMasterSlave && exposure_us > 0 &&
      !(exposure_us >= auto_exposure.exposure_min_us && exposure_us <= auto_exposure.exposure_max_us)) {
    p.push_back("exposure_us (master_slave: where auto-exposure starts) must be 0 or within exposure_auto_min_us.."
                "exposure_auto_max_us");
  }
  return p;
}

std::vector<std::string> AravisStereoConfig::validate() const {
  std::vector<std::string> p = left.validate("left");
  const auto r = right.validate("right");
  p.insert(p.end(), r.begin(), r.end());
  const auto c = controls.validate();
  p.insert(p.end(), c.begin(), c.end());
  if (left.pixel_format != right.pixel_format) p.push_back("left and right pixel_format differ");
  if (!(ptp_timeout_s > 0 && ptp_timeout_s <= 120)) p.push_back("ptp_timeout_s must be in (0, 120]");
  if (!(max_skew_s >= 0 && max_skew_s < 1)) p.push_back("max_skew_s must be in [0, 1)");
  if (!(frame_timeout_s > 0.05 && frame_timeout_s <= 60)) p.push_back("frame_timeout_s must be in (0.05, 60]");
  if (!(max_backoff_s >= 0.25 && max_backoff_s <= 300)) p.push_back("max_backoff_s must be in [0.25, 300]");
  if (!left.id.empty() && left.id == right.id) p.push_back("left and right are the same camera '" + left.id + "'");
  return p;
}

double AravisStereoConfig::effectiveMaxSkewS() const {
  if (max_skew_s > 0) return max_skew_s;
  switch (sync) {
    case TriggerMode::kHardware: return 0.001;
    case TriggerMode::kSoftware: return 0.005;
    case TriggerMode::kFreeRun: break;
  }
  return 0.5 / controls.rate_hz;
}

AravisStereoSource::AravisStereoSource(const AravisStereoConfig& config, Log log)
    : config_(config), log_(std::move(log)), pairer_(static_cast<std::int64_t>(config.effectiveMaxSkewS() * 1e9)) {
  const auto problems = config_.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid stereo camera configuration", problems));
  for (int s = 0; s < 2; ++s) {
    sides_[s] = std::make_unique<Side>();
    sides_[s]->settings = s == 0 ? config_.left : config_.right;
    sides_[s]->settings.trigger = config_.sync;
  }
  controls_ = config_.controls;
  wanted_ = startExposure(controls_);
}

std::vector<std::string> AravisStereoSource::reconfigure(const StereoControls& controls) {
  auto problems = controls.validate();
  if (!problems.empty()) return problems;
  std::lock_guard<std::mutex> lock(controls_mutex_);
  const StereoControls before = controls_;
  controls_ = controls;
  ++controls_generation_;
  const AutoExposureSettings &a = controls.auto_exposure, &b = before.auto_exposure;
  if (controls.exposure_sync != before.exposure_sync || controls.exposure_us != before.exposure_us ||
      controls.gain != before.gain || controls.exposure_sync == ExposureSync::kFixed) {
    wanted_ = startExposure(controls);
    ++wanted_generation_;
  } else if (a.exposure_min_us != b.exposure_min_us || a.exposure_max_us != b.exposure_max_us ||
             a.gain_min_db != b.gain_min_db || a.gain_max_db != b.gain_max_db) {
    wanted_.exposure_us = std::clamp(wanted_.exposure_us, a.exposure_min_us, a.exposure_max_us);
    if (controls.gain < 0) wanted_.gain_db = std::clamp(wanted_.gain_db, a.gain_min_db, a.gain_max_db);
    ++wanted_generation_;
  }
  if (controls.rate_hz != before.rate_hz && config_.sync == TriggerMode::kFreeRun) {
    AravisStereoConfig changed = config_;  // the pairing tolerance is half the new period
    changed.controls.rate_hz = controls.rate_hz;
    std::lock_guard<std::mutex> pair_lock(pair_mutex_);
    pairer_.setMaxSkewNs(static_cast<std::int64_t>(changed.effectiveMaxSkewS() * 1e9));
  }
  return problems;
}

StereoControls AravisStereoSource::controls() const {
  std::lock_guard<std::mutex> lock(controls_mutex_);
  return controls_;
}

AravisStereoSource::~AravisStereoSource() { stop(); }

void AravisStereoSource::start(FrameCallback callback) {
  if (running_) return;
  delivery_ = std::make_unique<PairDelivery>(std::move(callback), kMaxQueuedPairs);
  running_ = true;
  for (int s = 0; s < 2; ++s) sides_[s]->thread = std::thread([this, s] { runCamera(s); });
}

void AravisStereoSource::stop() {
  if (!running_) return;
  running_ = false;
  for (auto& side : sides_) {
    if (side->thread.joinable()) side->thread.join();
    std::lock_guard<std::mutex> lock(side->mutex);
    side->status.state = CameraState::kClosed;
  }
  std::unique_ptr<PairDelivery> delivery;
  {
    std::lock_guard<std::mutex> lock(pair_mutex_);
    delivered_before_ = delivery_->counts();
    delivery = std::move(delivery_);
  }
  delivery.reset();  // joins its thread (outside the lock: a callback may ask for status()): no callback after this
}

StereoStatus AravisStereoSource::status() {
  StereoStatus out;
  CameraStatus* targets[2] = {&out.left, &out.right};
  for (int s = 0; s < 2; ++s) {
    std::lock_guard<std::mutex> lock(sides_[s]->mutex);
    *targets[s] = sides_[s]->status;  // its stream statistics as its own thread last read them
  }
  std::lock_guard<std::mutex> lock(pair_mutex_);
  out.pairs = pairer_.pairs();
  out.unpaired = pairer_.dropped();
  if (const auto& miss = pairer_.lastMiss()) {
    const bool left = miss->side == FramePairer<CameraFrame>::kLeft;
    char text[160];
    if (miss->other_seen) {
      std::snprintf(text, sizeof text, "%s frame at %.3f s: the nearest %s frame %+.1f ms from it (pairing within %.1f ms)",
                    left ? "left" : "right", miss->time_ns / 1e9, left ? "right" : "left",
                    miss->other_minus_this_ns / 1e6, pairer_.maxSkewNs() / 1e6);
    } else {
      std::snprintf(text, sizeof text, "%s frame at %.3f s: no %s frame came", left ? "left" : "right",
                    miss->time_ns / 1e9, left ? "right" : "left");
    }
    out.last_unpaired = text;
  }
  out.last_skew_ms = last_skew_ms_;
  out.ptp_stamps = out.left.ptp_settled && out.right.ptp_settled;
  const PairDelivery::Counts delivery = delivery_ ? delivery_->counts() : delivered_before_;
  out.out_of_order = delivery.out_of_order;
  out.overflowed = delivery.overflowed;
  return out;
}

void AravisStereoSource::runCamera(int s) {
  Side& side = *sides_[s];
  const std::string name = s == 0 ? "left" : "right";
  double backoff = 0.25;
  auto sleepFor = [this](double seconds) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (running_ && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  };
  while (running_) {
    std::shared_ptr<AravisCamera> camera;
    {
      std::lock_guard<std::mutex> lock(side.mutex);
      side.status.state = side.status.outages > 0 ? CameraState::kReconnecting : CameraState::kOpening;
    }
    try {
      // Opened with the controls in use now (after an outage: the exposure master_slave had reached).
      CameraSettings settings = side.settings;
      {
        std::lock_guard<std::mutex> lock(controls_mutex_);
        side.in_use = controls_;
        side.seen_controls = controls_generation_;
        side.seen_wanted = wanted_generation_;
        settings.frame_rate_hz = controls_.rate_hz;
        settings.packet_delay_ns = controls_.packet_delay_ns;
        settings.exposure_auto_min_us = controls_.auto_exposure.exposure_min_us;
        settings.exposure_auto_max_us = controls_.auto_exposure.exposure_max_us;
        if (controls_.exposure_sync != ExposureSync::kIndependent) {
          settings.exposure_us = wanted_.exposure_us;
          settings.gain = wanted_.gain_db;
        } else {
          if (controls_.exposure_us > 0) settings.exposure_us = controls_.exposure_us;
          if (controls_.gain >= 0) settings.gain = controls_.gain;
        }
      }
      std::vector<std::string> report;
      camera = std::make_shared<AravisCamera>(settings, report);
      for (const auto& line : report) log_(false, name + " camera: " + line);
      side.gain_db = gainInDb(*camera);
      side.applied = {exposureUs(*camera), gain(*camera)};
      side.camera_auto = side.in_use.exposure_sync == ExposureSync::kIndependent &&
                         ((settings.exposure_us <= 0 && camera->available("ExposureAuto")) ||
                          (settings.gain < 0 && camera->available("GainAuto")));
      side.previous = side.applied;
      side.applied_ns = 0;
      startPtp(s, *camera);
      camera->start();
    } catch (const std::runtime_error& e) {
      {
        std::lock_guard<std::mutex> lock(side.mutex);
        side.status.last_error = e.what();
      }
      log_(true, name + " camera: " + e.what() + "; retrying in " + std::to_string(backoff) + " s");
      sleepFor(backoff);
      backoff = std::min(backoff * 2, config_.max_backoff_s);
      continue;
    }
    {
      std::lock_guard<std::mutex> lock(side.mutex);
      side.status.description = camera->description();
      side.status.unsupported = camera->unsupported();
      if (config_.ptp && !side.status.ptp_settled) side.status.unsupported.push_back("PTP: " + side.status.ptp);
      if (side.in_use.exposure_sync == ExposureSync::kMasterSlave && side.in_use.gain < 0 && !side.gain_db) {
        side.status.unsupported.push_back("Gain in dB: the camera has GainRaw only, so master_slave holds its gain at " +
                                          std::to_string(side.applied.gain_db) + " (raw) and sets the exposure alone");
      }
      side.status.state = CameraState::kStreaming;
      side.status.exposure = side.applied;
      side.status.gain_unit = side.gain_db ? "dB" : "raw";
      side.clock = ClockMapper();
      side.ids = FrameIdTracker();
    }
    {
      std::lock_guard<std::mutex> lock(pair_mutex_);
      pairer_.clear();
    }
    auto last_frame = std::chrono::steady_clock::now();
    auto statistics_due = last_frame;
    std::string lost_reason;
    bool reopen = false;
    // A camera that opens but never sends a frame (its stream not yet up after a power cycle, GVSP blocked) has
    // not come back: the outage goes on, counted once, and the next attempt waits as after a failed open.
    bool streamed = false;
    // Software sync: each camera's thread fires its TriggerSoftware on the same schedule (TriggerSchedule: ticks
    // of the wall clock), so a camera that hangs or vanishes never delays the other's trigger.
    TriggerSchedule schedule(side.in_use.rate_hz);
    std::int64_t tick_us = schedule.nextAfter(hostNowNs() / 1000);
    while (running_) {
      if (!applyChanges(s, *camera)) {
        reopen = true;
        break;
      }
      if (TriggerSchedule(side.in_use.rate_hz).periodUs() != schedule.periodUs()) {
        schedule = TriggerSchedule(side.in_use.rate_hz);
        tick_us = schedule.nextAfter(hostNowNs() / 1000);
      }
      int wait_ms = 100;
      if (config_.sync == TriggerMode::kSoftware) {
        const std::int64_t now_us = hostNowNs() / 1000;
        if (now_us >= tick_us) {
          try {
            camera->trigger();
          } catch (const std::runtime_error&) {
            // Unreachable: the frame timeout below notices and reopens it.
          }
        }
        tick_us = schedule.keepOrRenew(tick_us, now_us);
        wait_ms = static_cast<int>((tick_us - now_us + 999) / 1000);
      }
      if (std::chrono::steady_clock::now() >= statistics_due) {
        const CameraStatistics statistics = camera->statistics();
        std::lock_guard<std::mutex> lock(side.mutex);
        side.status.stream = statistics;
        statistics_due = std::chrono::steady_clock::now() + kStatisticsPeriod;
      }
      CameraFrame frame;
      if (camera->next(frame, std::min(wait_ms, 100))) {
        last_frame = std::chrono::steady_clock::now();
        if (!streamed) {
          streamed = true;
          backoff = 0.25;
        }
        std::int64_t capture_ns = 0;
        bool ptp = false;
        {
          std::lock_guard<std::mutex> lock(side.mutex);
          ++side.status.frames;
          side.status.missed_frames += side.ids.missedBefore(frame.frame_id);
          capture_ns = side.clock.toHost(frame.device_ns, frame.host_ns);
          ptp = side.status.ptp_settled;
          frame.capture.temperature_c = side.status.stream.temperature_c;
          frame.capture.camera = side.status.description;
        }
        if (ptp) {
          // Both on one PTP timescale: one offset to the host clock for both (the smaller estimate, the one
          // with the shorter transfer delay), so a pair's stamps differ by exactly their PTP difference.
          Side& other = *sides_[1 - s];
          std::lock_guard<std::mutex> lock(other.mutex);
          if (other.status.ptp_settled && other.status.frames > 0) {
            capture_ns = static_cast<std::int64_t>(frame.device_ns) + std::min(side.clock.offsetNs(), other.clock.offsetNs());
          } else {
            ptp = false;
          }
        }
        if (side.camera_auto) {
          // The camera's own auto functions move exposure and gain: read them as each frame arrives.
          try {
            side.applied = {exposureUs(*camera), gain(*camera)};
            side.applied_ns = capture_ns;
            std::lock_guard<std::mutex> lock(side.mutex);
            side.status.exposure = side.applied;
          } catch (const std::runtime_error&) {
            // Unreachable camera: the frame timeout notices; this frame keeps the last values read.
          }
        }
        const Exposure& taken = capture_ns >= side.applied_ns ? side.applied : side.previous;
        frame.capture.frame_id = frame.frame_id;
        frame.capture.device_ns = frame.device_ns;
        frame.capture.ptp = ptp;
        frame.capture.exposure_us = taken.exposure_us;
        frame.capture.gain = taken.gain_db;
        frame.capture.gain_unit = side.gain_db ? "dB" : "raw";
        if (s == 0 && side.in_use.exposure_sync == ExposureSync::kMasterSlave) meter(frame);
        deliver(s, std::move(frame), capture_ns);
        continue;
      }
      if (!camera->connected()) {
        lost_reason = "control connection lost";
      } else if (std::chrono::duration<double>(std::chrono::steady_clock::now() - last_frame).count() >
                 config_.frame_timeout_s) {
        lost_reason = "no frame for " + std::to_string(config_.frame_timeout_s) + " s";
      }
      if (!lost_reason.empty()) break;
    }
    // Lost before its first frame: a failed attempt to reopen (retried after the back-off), not another outage.
    const bool never_streamed = !lost_reason.empty() && !streamed;
    if (never_streamed) lost_reason = "opened, but " + lost_reason;
    {
      std::lock_guard<std::mutex> lock(side.mutex);
      if (!lost_reason.empty()) {
        if (streamed) ++side.status.outages;
        side.status.last_error = lost_reason;
        side.status.state = side.status.outages > 0 ? CameraState::kReconnecting : CameraState::kOpening;
      }
    }
    if (!lost_reason.empty()) {
      log_(true, name + " camera " + camera->description() + ": " + lost_reason +
                     (streamed ? "; reopening" : "; retrying in " + std::to_string(backoff) + " s"));
    }
    if (reopen) log_(false, name + " camera: exposure_sync changed to or from independent; reopening");
    try {
      camera->stop();
    } catch (const std::runtime_error&) {
      // The camera is gone; closing is all that is left.
    }
    camera.reset();
    if (never_streamed) {
      sleepFor(backoff);
      backoff = std::min(backoff * 2, config_.max_backoff_s);
    }
  }
}

bool AravisStereoSource::applyChanges(int s, AravisCamera& camera) {
  Side& side = *sides_[s];
  StereoControls c;
  Exposure wanted;
  {
    std::lock_guard<std::mutex> lock(controls_mutex_);
    if (side.seen_controls == controls_generation_ && side.seen_wanted == wanted_generation_) return true;
    c = controls_;
    wanted = wanted_;
    side.seen_controls = controls_generation_;
    side.seen_wanted = wanted_generation_;
  }
  const StereoControls before = side.in_use;
  const bool independent = c.exposure_sync == ExposureSync::kIndependent;
  if (independent != (before.exposure_sync == ExposureSync::kIndependent) ||
      (independent && (c.exposure_us != before.exposure_us || c.gain != before.gain ||
                       c.auto_exposure.exposure_min_us != before.auto_exposure.exposure_min_us ||
                       c.auto_exposure.exposure_max_us != before.auto_exposure.exposure_max_us))) {
    return false;  // the camera's own auto functions are set up at opening
  }
  side.in_use = c;
  const std::string name = s == 0 ? "left" : "right";
  try {
    if (c.packet_delay_ns != before.packet_delay_ns) camera.setInteger(firstAvailable(camera, {"GevSCPD"}), c.packet_delay_ns);
    if (c.rate_hz != before.rate_hz && config_.sync == TriggerMode::kFreeRun) {
      setFloatFeature(camera, {"AcquisitionFrameRate", "AcquisitionFrameRateAbs"}, c.rate_hz);
    }
    if (!independent && !sameExposure(wanted, side.applied)) {
      const std::int64_t sent_ns = hostNowNs();
      Exposure read{setExposureUs(camera, wanted.exposure_us), side.applied.gain_db};
      if (std::abs(wanted.gain_db - side.applied.gain_db) >= 0.01) read.gain_db = setGain(camera, wanted.gain_db);
      side.previous = side.applied;
      side.applied = read;
      side.applied_ns = sent_ns;
      std::lock_guard<std::mutex> lock(side.mutex);
      side.status.exposure = read;
    }
  } catch (const std::runtime_error& e) {
    std::lock_guard<std::mutex> lock(side.mutex);
    side.status.last_error = e.what();
    log_(true, name + " camera: " + e.what());
  }
  return true;
}

void AravisStereoSource::meter(const CameraFrame& frame) {
  StereoControls c;
  {
    std::lock_guard<std::mutex> lock(controls_mutex_);
    c = controls_;
  }
  if (c.exposure_sync != ExposureSync::kMasterSlave) return;
  AutoExposureSettings law = c.auto_exposure;
  const Exposure taken{frame.capture.exposure_us, frame.capture.gain};
  // Gain moves only when asked for (gain < 0) and both cameras take it in dB.
  if (c.gain >= 0 || !sides_[0]->gain_db || !sides_[1]->gain_db) law.gain_min_db = law.gain_max_db = taken.gain_db;
  const Exposure next = nextExposure(law, meanBrightness(frame.image, law.roi), taken);
  std::lock_guard<std::mutex> lock(controls_mutex_);
  if (controls_.exposure_sync == ExposureSync::kMasterSlave && !sameExposure(next, wanted_)) {
    wanted_ = next;
    ++wanted_generation_;
  }
}

void AravisStereoSource::startPtp(int s, AravisCamera& camera) {
  Side& side = *sides_[s];
  const std::string name = s == 0 ? "left" : "right";
  std::string state = "off";
  bool settled = false;
  if (config_.ptp) {
    try {
      const std::string feature = enablePtp(camera);
      if (feature.empty()) {
        state = "the camera has neither PtpEnable nor GevIEEE1588, so its frames are stamped by the clock mapping";
      } else {
        const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(config_.ptp_timeout_s);
        std::string port = ptpStatus(camera);
        while (running_ && !ptpSettled(port) && std::chrono::steady_clock::now() < end) {
          std::this_thread::sleep_for(std::chrono::milliseconds(100));
          port = ptpStatus(camera);
        }
        settled = ptpSettled(port);
        state = settled ? port
                        : "not Master or Slave " + std::to_string(config_.ptp_timeout_s) + " s after " + feature +
                              " (state " + port + "), so its frames are stamped by the clock mapping";
      }
    } catch (const std::runtime_error& e) {
      state = std::string(e.what()) + ", so its frames are stamped by the clock mapping";
    }
    log_(!settled, name + " camera: PTP requested: " + state);
  }
  std::lock_guard<std::mutex> lock(side.mutex);
  side.status.ptp = state;
  side.status.ptp_settled = settled;
}

void AravisStereoSource::deliver(int side, CameraFrame frame, std::int64_t capture_ns) {
  frame.capture_ns = capture_ns;
  // Pairs are formed and queued under one lock, so they leave the delivery thread in the order they formed,
  // whichever camera thread completed them.
  std::lock_guard<std::mutex> lock(pair_mutex_);
  auto pair = pairer_.add(side == 0 ? FramePairer<CameraFrame>::kLeft : FramePairer<CameraFrame>::kRight, capture_ns,
                          std::move(frame));
  if (!pair) return;
  last_skew_ms_ = std::abs(static_cast<double>(pair->first.capture_ns - pair->second.capture_ns)) / 1e6;
  StereoFrame out;
  out.left = std::move(pair->first.image);
  out.right = std::move(pair->second.image);
  out.left_pixels = std::move(pair->first.pixels);
  out.right_pixels = std::move(pair->second.pixels);
  out.encoding = pair->first.encoding;
  out.capture_time_ns = pair->first.capture_ns;  // the left capture; the right one is within the skew
  out.left_capture = std::move(pair->first.capture);
  out.right_capture = std::move(pair->second.capture);
  delivery_->push(std::move(out));
}

}  // namespace underwater_stereo
