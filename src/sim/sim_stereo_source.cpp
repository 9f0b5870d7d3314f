// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/sim/sim_stereo_source.h"

#include <chrono>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {
namespace sim {

std::vector<std::string> SimSourceConfig::validate() const {
  std::vector<std::string> problems;
  if (!(rate_hz > 0.0 && rate_hz <= 200.0)) {
    problems.push_back("rate_hz = " + std::to_string(rate_hz) + " is outside (0, 200]");
  }
  if (loop_frames < 0 || loop_frames > 10000) {
    problems.push_back("loop_frames = " + std::to_string(loop_frames) + " is outside [0, 10000]");
  }
  return problems;
}

SimStereoSource::SimStereoSource(std::shared_ptr<const Renderer> renderer, const SimSourceConfig& config,
                                 ErrorLog log_error)
    : renderer_(std::move(renderer)), config_(config), log_error_(std::move(log_error)) {
  if (!renderer_) throw std::invalid_argument("SimStereoSource: no renderer");
  const auto problems = config_.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid simulated source config", problems));
}

SimStereoSource::~SimStereoSource() { stop(); }

StereoFrame SimStereoSource::frame(std::uint64_t sequence) {
  const std::uint64_t scene_index = config_.loop_frames > 0 ? sequence % config_.loop_frames : sequence;
  StereoFrame out;
  const auto cached = cache_.find(scene_index);
  if (cached != cache_.end()) {
    out = cached->second;
  } else {
    RenderedPair pair = renderer_->render(static_cast<double>(scene_index) / config_.rate_hz, scene_index);
    out.left = pair.left;
    out.right = pair.right;
    out.encoding = pair.encoding;
    out.ground_truth = std::move(pair.ground_truth);
    out.camera_pose_world = pair.camera_pose;
    if (config_.loop_frames > 0) {
      out.left = cacheImage(scene_index, 0, out.left);
      out.right = cacheImage(scene_index, 1, out.right);
      cache_[scene_index] = out;
    }
  }
  out.sequence = sequence;
  return out;
}

cv::Mat SimStereoSource::cacheImage(std::uint64_t scene_index, int side, const cv::Mat& image) {
  if (loop_images_.empty()) loop_images_.create(2 * config_.loop_frames * image.rows, image.cols, image.type());
  if (image.cols != loop_images_.cols || image.type() != loop_images_.type() ||
      2 * config_.loop_frames * image.rows != loop_images_.rows) {
    throw std::runtime_error("SimStereoSource: the render of loop frame " + std::to_string(scene_index) + " is " +
                             std::to_string(image.cols) + "x" + std::to_string(image.rows) + " of OpenCV type " +
                             std::to_string(image.type()) + ", the loop's images are " +
                             std::to_string(loop_images_.cols) + "x" +
                             std::to_string(loop_images_.rows / (2 * config_.loop_frames)) + " of type " +
                             std::to_string(loop_images_.type()) + "; the pair is not delivered");
  }
  const int first_row = static_cast<int>(2 * scene_index + side) * image.rows;
  cv::Mat slot = loop_images_.rowRange(first_row, first_row + image.rows);
  image.copyTo(slot);
  return slot;
}

void SimStereoSource::start(FrameCallback callback) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (running_) throw std::logic_error("SimStereoSource::start: already running");
    running_ = true;
  }
  thread_ = std::thread([this, cb = std::move(callback)] { run(cb); });
}

void SimStereoSource::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    running_ = false;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void SimStereoSource::run(FrameCallback callback) {
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / config_.rate_hz));
  auto next = Clock::now();
  for (std::uint64_t sequence = 0;; ++sequence) {
    StereoFrame pair;
    try {
      pair = frame(sequence);
    } catch (const std::exception& e) {  // one pair lost, reported; the source goes on
      if (log_error_) log_error_(e.what());
      pair = StereoFrame();
    }
    {
      std::unique_lock<std::mutex> lock(mutex_);
      if (wake_.wait_until(lock, next, [this] { return !running_; })) return;
    }
    if (!pair.left.empty()) callback(pair);
    next += period;
    // Behind by more than a period (slow live rendering): restart the schedule instead of bursting.
    if (Clock::now() > next + period) next = Clock::now();
  }
}

}  // namespace sim
}  // namespace underwater_stereo
