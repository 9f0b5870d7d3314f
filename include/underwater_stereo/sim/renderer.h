// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Ray-casting renderer for simulated underwater stereo pairs with exact ground truth.

#include <opencv2/core.hpp>

#include <vector>

#include "underwater_stereo/common/ground_truth.h"
#include "underwater_stereo/sim/scene.h"
#include "underwater_stereo/sim/stereo_rig.h"

namespace underwater_stereo {
namespace sim {

/// One rendered stereo pair.
struct RenderedPair {
  cv::Mat left;    ///< CV_8UC1 (bayer_rggb8) or CV_8UC3 (bgr8), raw: distorted, unrectified
  cv::Mat right;
  std::string encoding;
  double time_s = 0.0;          ///< scene time the pair shows
  Eigen::Isometry3d camera_pose = Eigen::Isometry3d::Identity();  ///< the left optical frame in the world frame
  std::vector<GroundTruthObject> ground_truth;  ///< one per scene object, in scene order
  cv::Mat left_labels;          ///< CV_16UC1: 1 + index of the object each left pixel sees, 0 for water/seabed
};

/// Renders a scene. Construction precomputes each pixel's ray (undoing lens distortion); render()
/// is const and may be called from several threads at once.
class Renderer {
 public:
  /// @throw std::invalid_argument when the scene does not validate.
  explicit Renderer(Scene scene);

  /// Renders the pair at scene time `time_s`. `frame_index` seeds the sensor noise, so the same
  /// (time, index) gives the same images.
  /// @throw std::invalid_argument when a camera lies inside an object then (camerasInside): its view would be the
  /// object's inside and its ground truth the whole image.
  RenderedPair render(double time_s, std::uint64_t frame_index) const;

  /// Every object that holds a camera at scene time `time_s` ("objects[i] (name): the left camera lies inside it at
  /// time T s"): a moving camera or object may meet later than time 0, which construction checks.
  std::vector<std::string> camerasInside(double time_s) const;

  /// Every object that holds a camera at one of the frames 0 .. frames - 1 rendered at `rate_hz` (frame k at time
  /// k / rate_hz), once per object and camera with its frames as ranges ("objects[i] (name): the left camera lies
  /// inside it at frames 3-40, 52 (of 60 at 15 Hz)"; the first ten ranges, then how many more): a check of a whole
  /// run before anything is rendered. @throw std::invalid_argument when frames < 0 or rate_hz is not positive.
  std::vector<std::string> camerasInside(int frames, double rate_hz) const;

  /// A renderer of `scene` that shares this one's pixel rays (the costly part of construction), for many
  /// scenes seen by one head. @throw std::invalid_argument when scene.rig differs from this renderer's or
  /// the scene does not validate.
  Renderer withScene(Scene scene) const;

  const Scene& scene() const { return scene_; }
  const StereoRig& rig() const { return rig_; }
  const StereoCalibration& calibration() const { return rig_.calibration(); }

 private:
  Renderer(Scene scene, const Renderer& rays_from);

  Scene scene_;
  StereoRig rig_;
  cv::Mat left_rays_;   ///< CV_32FC3 unit ray per pixel in the left optical frame
  cv::Mat right_rays_;  ///< same for the right camera
};

/// Mosaics a BGR image into a single-channel RGGB Bayer pattern (R at (0,0)), as the cameras deliver.
cv::Mat mosaicRggb(const cv::Mat& bgr);

}  // namespace sim
}  // namespace underwater_stereo
