// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/aravis_stereo_source.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {

namespace {
/// Pairs waiting for a slow callback before the oldest is dropped.
constexpr std::size_t kMaxQueuedPairs = 4;
/// The camera thread refreshes its stream statistics (a GVCP read) this often.
constexpr std::chrono::milliseconds kStatisticsPeriod(1000);
}  // namespace

struct AravisStereoSource::Side {
  CameraSettings settings;
  std::mutex mutex;                       ///< guards status (the camera itself is used by its thread only)
  ClockMapper clock;
  FrameIdTracker ids;
  CameraStatus status;
  std::thread thread;
};

std::vector<std::string> AravisStereoConfig::validate() const {
  std::vector<std::string> p = left.validate("left");
  const auto r = right.validate("right");
  p.insert(p.end(), r.begin(), r.end());
  if (left.pixel_format != right.pixel_format) p.push_back("left and right pixel_format differ");
  if (!(rate_hz > 0 && rate_hz <= 200)) p.push_back("rate_hz must be in (0, 200]");
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
  return 0.5 / rate_hz;
}

AravisStereoSource::AravisStereoSource(const AravisStereoConfig& config, Log log)
    : config_(config), log_(std::move(log)), pairer_(static_cast<std::int64_t>(config.effectiveMaxSkewS() * 1e9)) {
  const auto problems = config_.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid stereo camera configuration", problems));
  for (int s = 0; s < 2; ++s) {
    sides_[s] = std::make_unique<Side>();
    sides_[s]->settings = s == 0 ? config_.left : config_.right;
    sides_[s]->settings.trigger = config_.sync;
    sides_[s]->settings.frame_rate_hz = config_.rate_hz;
  }
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
    side->status.state = "closed";
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
  out.last_skew_ms = last_skew_ms_;
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
      side.status.state = side.status.outages > 0 ? "reconnecting" : "opening";
    }
    try {
      std::vector<std::string> report;
      camera = std::make_shared<AravisCamera>(side.settings, report);
      for (const auto& line : report) log_(false, name + " camera: " + line);
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
    backoff = 0.25;
    {
      std::lock_guard<std::mutex> lock(side.mutex);
      side.status.description = camera->description();
      side.status.unsupported = camera->unsupported();
      side.status.state = "streaming";
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
    // Software sync: each camera's thread fires its TriggerSoftware on the same schedule (ticks of the steady
    // clock), so a camera that hangs or vanishes never delays the other's trigger.
    const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(1.0 / config_.rate_hz));
    auto tick = std::chrono::steady_clock::time_point(
        (std::chrono::steady_clock::now().time_since_epoch() / period + 1) * period);
    while (running_) {
      int wait_ms = 100;
      if (config_.sync == TriggerMode::kSoftware) {
        const auto now = std::chrono::steady_clock::now();
        if (now >= tick) {
          try {
            camera->trigger();
          } catch (const std::runtime_error&) {
            // Unreachable: the frame timeout below notices and reopens it.
          }
          while (tick <= now) tick += period;
        }
        wait_ms = static_cast<int>(std::chrono::duration_cast<std::chrono::milliseconds>(tick - now).count()) + 1;
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
        std::int64_t capture_ns = 0;
        {
          std::lock_guard<std::mutex> lock(side.mutex);
          ++side.status.frames;
          side.status.missed_frames += side.ids.missedBefore(frame.frame_id);
          capture_ns = side.clock.toHost(frame.device_ns, frame.host_ns);
        }
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
    {
      std::lock_guard<std::mutex> lock(side.mutex);
      if (!lost_reason.empty()) {
        ++side.status.outages;
        side.status.last_error = lost_reason;
        side.status.state = "reconnecting";
      }
    }
    if (!lost_reason.empty()) log_(true, name + " camera " + camera->description() + ": " + lost_reason + "; reopening");
    try {
      camera->stop();
    } catch (const std::runtime_error&) {
      // The camera is gone; closing is all that is left.
    }
    camera.reset();
  }
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
  out.encoding = pair->first.encoding;
  out.capture_time_ns = pair->first.capture_ns;  // the left capture; the right one is within the skew
  delivery_->push(std::move(out));
}

}  // namespace underwater_stereo
