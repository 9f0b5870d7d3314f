// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The simulated stereo head as a StereoSource: renders the scene's sequence at a fixed rate.

#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "underwater_stereo/camera/stereo_source.h"
#include "underwater_stereo/sim/renderer.h"

namespace underwater_stereo {
namespace sim {

struct SimSourceConfig {
  double rate_hz = 15.0;         ///< [Hz] pairs per second; frame k shows scene time k / rate_hz
  int loop_frames = 0;           ///< > 0: render frames 0..loop_frames-1 once each and then repeat them
                                 ///< (keeps up at full size); 0: render every frame live (motion never repeats)

  std::vector<std::string> validate() const;
};

/// Renders pairs in its own thread and delivers them at rate_hz (slower when live rendering cannot keep up).
class SimStereoSource : public StereoSource {
 public:
  /// Receives the message of each pair the source thread cannot make (frame() threw); that pair is skipped and
  /// the thread goes on with the next.
  using ErrorLog = std::function<void(const std::string& message)>;

  /// @throw std::invalid_argument when the config does not validate.
  SimStereoSource(std::shared_ptr<const Renderer> renderer, const SimSourceConfig& config, ErrorLog log_error = {});
  ~SimStereoSource() override;

  void start(FrameCallback callback) override;
  void stop() override;

  /// Renders (or takes from the loop cache) pair number `sequence`.
  /// @throw std::runtime_error when a render's image size or type differs from the loop's first (naming both).
  StereoFrame frame(std::uint64_t sequence);


 private:
  void run(FrameCallback callback);
  /// Copies one rendered image into its slot of loop_images_ (allocated at the first call) and returns the slot.
  cv::Mat cacheImage(std::uint64_t scene_index, int side, const cv::Mat& image);

  std::shared_ptr<const Renderer> renderer_;
  SimSourceConfig config_;
  ErrorLog log_error_;
  std::map<std::uint64_t, StereoFrame> cache_;  ///< only with loop_frames > 0; touched by the source thread only
  /// The cached loop's images, all in one buffer (cache_'s images are row ranges of it): one allocation above
  /// glibc's mmap threshold is unmapped when freed, where 2 x loop_frames image-sized ones would stay in the
  /// heap after the source is destroyed (the launch files' MALLOC_TRIM_THRESHOLD_) and move its RSS.
  cv::Mat loop_images_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool running_ = false;  ///< guarded by mutex_
  std::thread thread_;
};

}  // namespace sim
}  // namespace underwater_stereo
