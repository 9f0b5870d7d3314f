// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file How each pixel stands out from the water around it.
///
/// Through water a camera sees I = J t + B (1 - t) per channel (t = e^(-b d)): the object's own colour J
/// fades towards the water's veiling colour B with range. Whatever the water, an object differs from the
/// water around it in a direction set by its own colour; the magnitude shrinks with range. So the detector
/// does not look for fixed hues: it measures, per pixel, the log ratio of the pixel to the local water colour
/// (B estimated per frame as a heavily smoothed median of the image, objects being small against it), and
/// how unusual that ratio is in this frame (normalised by the frame's own spread, so clear and turbid water,
/// bright and dim frames give comparable numbers).

#include <opencv2/core.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace underwater_stereo {

struct WaterContrastConfig {
  /// The water colour is the median over windows of about 5 / background_scale pixels of the searched image:
  /// much larger than the objects looked for (0.03: a 160-px window on a 640-px wide image).
  double background_scale = 1.0 / 32.0;
  /// Offset added to pixel and water values before their ratio (keeps the dark noise floor from exploding).
  double ratio_offset = 4.0;
  /// Objects left out of the water colour: regions that stand out from a first estimate of the water at this
  /// saliency level (in the frame's own spreads, seen at a quarter of a window cell) are taken with their convex
  /// hulls (an object larger than the window stands out only at its rim), and the water under them is filled in
  /// smoothly from the water around them. 0: off (an object larger than the window is its own water in the
  /// middle, so only its rim stands out).
  double object_level = 32.0;

  std::vector<std::string> validate() const;
};

/// A frame's spread of contrast, per saliency kind: median and median absolute deviation per channel.
struct ContrastStats {
  cv::Vec3f median[2];
  cv::Vec3f spread[2];  ///< MAD, floored at 1e-3
};

/// Index of the saliency maps in WaterContrast::saliency.
enum class SaliencyKind { kChroma = 0, kFull = 1 };

struct WaterContrast {
  cv::Mat water;        ///< CV_8UC3: the local water colour (B, G, R) per pixel
  cv::Mat contrast;     ///< CV_32FC3: log((I + o) / (B + o)) per channel
  cv::Mat saliency[2];  ///< CV_32FC1: |(x - median) / spread| over the channels, x = chromaOf(contrast) (kChroma) or contrast (kFull)
  std::vector<float> row_max[2];  ///< the largest saliency of each row, per kind (where a cut can find anything)
  ContrastStats stats;
};

/// The chroma of a contrast: minus its mean over the channels (brightness removed).
cv::Vec3f chromaOf(const cv::Vec3f& contrast);

/// A contrast's two saliencies, chroma and full: its distance from the frame's median in the frame's spreads (what
/// WaterContrast::saliency holds per pixel; the detector's view check measures single colours with it).
struct Saliencies {
  cv::Vec3f m0, m1, k0, k1;  ///< medians and inverse spreads, chroma (0) and full (1)
  explicit Saliencies(const ContrastStats& stats)
      : m0(stats.median[0]),
        m1(stats.median[1]),
        k0(1.f / stats.spread[0][0], 1.f / stats.spread[0][1], 1.f / stats.spread[0][2]),
        k1(1.f / stats.spread[1][0], 1.f / stats.spread[1][1], 1.f / stats.spread[1][2]) {}
  void operator()(const cv::Vec3f& c, float& chroma, float& full) const {
    const cv::Vec3f h = chromaOf(c);
    const float a0 = (h[0] - m0[0]) * k0[0], b0 = (h[1] - m0[1]) * k0[1], c0 = (h[2] - m0[2]) * k0[2];
    const float a1 = (c[0] - m1[0]) * k1[0], b1 = (c[1] - m1[1]) * k1[1], c1 = (c[2] - m1[2]) * k1[2];
    chroma = std::sqrt(a0 * a0 + b0 * b0 + c0 * c0);
    full = std::sqrt(a1 * a1 + b1 * b1 + c1 * c1);
  }
  /// The saliency of `kind` alone.
  float operator()(const cv::Vec3f& c, SaliencyKind kind) const {
    float chroma, full;
    (*this)(c, chroma, full);
    return kind == SaliencyKind::kChroma ? chroma : full;
  }
};

/// The contrast of one colour (channels may be fractional: an average of pixels) against a water colour:
/// ln((colour + offset) / (water + offset)) per channel, as WaterContrast::contrast holds it per pixel.
cv::Vec3f contrastOf(const cv::Vec3f& colour, const cv::Vec3b& water, double offset);

/// Measures `bgr` (8-bit BGR) against its own water and spread, on `threads` threads (workOnThreads; the same
/// result whatever the number).
/// @throw std::invalid_argument when `bgr` is empty or not CV_8UC3, or the config is invalid.
WaterContrast measureWaterContrast(const cv::Mat& bgr, const WaterContrastConfig& config, int threads = 1);

/// Measures `bgr` against a given water colour (CV_8UC3 of its size) and spread: a part of the right frame
/// measured exactly like the left (both cameras look in the same direction through the same water, so the
/// water colour at a pixel is the same in both).
/// @throw std::invalid_argument on empty or mismatched images or an invalid config.
WaterContrast contrastAgainst(const cv::Mat& bgr, const cv::Mat& water, const ContrastStats& stats,
                              const WaterContrastConfig& config);

}  // namespace underwater_stereo
