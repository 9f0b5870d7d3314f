// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/water_contrast.h"

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "underwater_stereo/detection/area_shrink.h"
#include "underwater_stereo/detection/image_checks.h"
#include "underwater_stereo/detection/work_on_threads.h"

namespace underwater_stereo {
namespace {

/// Median window over the shrunken image: 5 cells (a cell is 1 / background_scale pixels).
constexpr int kMedianCells = 5;
/// The frame's spread is measured on every kStatsStep-th pixel of every kStatsStep-th row.
constexpr int kStatsStep = 4;

/// The element of `v` at v.size() / 2 in sorted order, as std::nth_element gives it, found by a radix select
/// over the floats' order-preserving bit patterns: a histogram of the upper 16 bits, then the one bin that holds
/// the median sorted. (nth_element over the ~36 000 samples of a 960x600 frame, twelve times, was a tenth of the
/// colour stage.) The values must not be NaN.
float medianOf(std::vector<float>& v) {
  const auto key = [](float f) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return bits & 0x80000000u ? ~bits : bits | 0x80000000u;
  };
  std::vector<std::uint32_t> counts(1u << 16, 0);
  for (const float f : v) ++counts[key(f) >> 16];
  std::size_t rank = v.size() / 2, bin = 0;
  while (rank >= counts[bin]) rank -= counts[bin++];
  std::vector<float> in_bin;
  in_bin.reserve(counts[bin]);
  for (const float f : v) {
    if (key(f) >> 16 == bin) in_bin.push_back(f);
  }
  std::nth_element(in_bin.begin(), in_bin.begin() + rank, in_bin.end());
  return in_bin[rank];
}

cv::Vec3f channelMedian(std::array<std::vector<float>, 3>& values) {
  cv::Vec3f m;
  for (int c = 0; c < 3; ++c) {
    if (values[c].empty()) return cv::Vec3f(0, 0, 0);
    m[c] = medianOf(values[c]);
  }
  return m;
}

/// Median and MAD per channel of `values` (modified).
void spreadOf(std::array<std::vector<float>, 3>& values, cv::Vec3f& median, cv::Vec3f& spread) {
  median = channelMedian(values);
  for (int c = 0; c < 3; ++c) {
    for (float& v : values[c]) v = std::abs(v - median[c]);
  }
  spread = channelMedian(values);
  for (int c = 0; c < 3; ++c) spread[c] = std::max(spread[c], 1e-3f);
}

/// log((I + o) / (B + o)) per channel, from a table of log(v + o).
struct ContrastOf {
  std::array<float, 256> log_table;
  explicit ContrastOf(double offset) {
    for (int v = 0; v < 256; ++v) log_table[v] = std::log(static_cast<float>(v + offset));
  }
  cv::Vec3f operator()(const cv::Vec3b& i, const cv::Vec3b& w) const {
    return cv::Vec3f(log_table[i[0]] - log_table[w[0]], log_table[i[1]] - log_table[w[1]], log_table[i[2]] - log_table[w[2]]);
  }
};

/// The frame's spread of chroma and contrast, on every kStatsStep-th pixel of every kStatsStep-th row (the two
/// spreads on `threads` threads).
ContrastStats statsOf(const cv::Mat& bgr, const cv::Mat& water, const ContrastOf& contrast, int threads) {
  std::array<std::vector<float>, 3> chroma, full;
  const std::size_t samples = std::size_t((bgr.rows + kStatsStep - 1) / kStatsStep) * ((bgr.cols + kStatsStep - 1) / kStatsStep);
  for (int k = 0; k < 3; ++k) {
    chroma[k].reserve(samples);
    full[k].reserve(samples);
  }
  for (int y = 0; y < bgr.rows; y += kStatsStep) {
    const auto* i = bgr.ptr<cv::Vec3b>(y);
    const auto* w = water.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; x += kStatsStep) {
      const cv::Vec3f c = contrast(i[x], w[x]), h = chromaOf(c);
      for (int k = 0; k < 3; ++k) {
        full[k].push_back(c[k]);
        chroma[k].push_back(h[k]);
      }
    }
  }
  ContrastStats stats;
  workOnThreads(2, threads, [&](int k) {
    spreadOf(k == 0 ? chroma : full, stats.median[k], stats.spread[k]);
  });
  return stats;
}

}  // namespace

cv::Vec3f chromaOf(const cv::Vec3f& contrast) {
  const float mean = (contrast[0] + contrast[1] + contrast[2]) * (1.f / 3.f);
  return cv::Vec3f(contrast[0] - mean, contrast[1] - mean, contrast[2] - mean);
}

std::vector<std::string> WaterContrastConfig::validate() const {
  std::vector<std::string> p;
  if (!(background_scale >= 0.005 && background_scale <= 0.5)) p.push_back("water.background_scale must be in [0.005, 0.5]");
  if (!(ratio_offset >= 0.5 && ratio_offset <= 64)) p.push_back("water.ratio_offset must be in [0.5, 64]");
  return p;
}

namespace {

/// The largest of n non-negative floats, several at a time.
float rowMax(const float* v, int n) {
  float m = 0.f;
  int x = 0;
#if CV_SIMD
  cv::v_float32 vm = cv::vx_setzero_f32();
  for (; x <= n - cv::v_float32::nlanes; x += cv::v_float32::nlanes) vm = cv::v_max(vm, cv::vx_load(v + x));
  m = cv::v_reduce_max(vm);
#endif
  for (; x < n; ++x) m = std::max(m, v[x]);
  return m;
}

/// Rows of the image per share of measureAgainstWater's work.
constexpr int kRowsPerShare = 32;

/// Contrast and saliency of `out` from its image and water (stats given, or measured when null), in one pass
/// per pixel (OpenCV's per-operation passes over float images cost ~5x more here; the chroma is not stored,
/// being the contrast minus its channel mean), on `threads` threads.
void measureAgainstWater(const cv::Mat& bgr, const WaterContrastConfig& config, const ContrastStats* stats,
                         int threads, WaterContrast& out) {
  const ContrastOf contrast(config.ratio_offset);
  out.stats = stats ? *stats : statsOf(bgr, out.water, contrast, threads);
  const cv::Vec3f m0 = out.stats.median[0], m1 = out.stats.median[1];
  const cv::Vec3f k0(1.f / out.stats.spread[0][0], 1.f / out.stats.spread[0][1], 1.f / out.stats.spread[0][2]);
  const cv::Vec3f k1(1.f / out.stats.spread[1][0], 1.f / out.stats.spread[1][1], 1.f / out.stats.spread[1][2]);
  out.contrast.create(bgr.size(), CV_32FC3);
  out.saliency[0].create(bgr.size(), CV_32FC1);
  out.saliency[1].create(bgr.size(), CV_32FC1);
  out.row_max[0].assign(bgr.rows, 0.f);
  out.row_max[1].assign(bgr.rows, 0.f);
  // Rows in parallel (each row's result is the same either way).
  workOnThreads((bgr.rows + kRowsPerShare - 1) / kRowsPerShare, threads, [&](int share) {
    for (int y = share * kRowsPerShare; y < std::min(bgr.rows, (share + 1) * kRowsPerShare); ++y) {
      const auto* i = bgr.ptr<cv::Vec3b>(y);
      const auto* w = out.water.ptr<cv::Vec3b>(y);
      auto* c = out.contrast.ptr<cv::Vec3f>(y);
      auto* s0 = out.saliency[0].ptr<float>(y);
      auto* s1 = out.saliency[1].ptr<float>(y);
      for (int x = 0; x < bgr.cols; ++x) c[x] = contrast(i[x], w[x]);
      // The saliencies, several pixels at a time: the same operations in the same order as the scalar tail
      // below (chromaOf's mean, then the normalised distances), so the result does not depend on the lanes.
      int x = 0;
#if CV_SIMD
      const float* cf = c[0].val;
      const cv::v_float32 third = cv::vx_setall_f32(1.f / 3.f);
      const cv::v_float32 vm0[3] = {cv::vx_setall_f32(m0[0]), cv::vx_setall_f32(m0[1]), cv::vx_setall_f32(m0[2])};
      const cv::v_float32 vm1[3] = {cv::vx_setall_f32(m1[0]), cv::vx_setall_f32(m1[1]), cv::vx_setall_f32(m1[2])};
      const cv::v_float32 vk0[3] = {cv::vx_setall_f32(k0[0]), cv::vx_setall_f32(k0[1]), cv::vx_setall_f32(k0[2])};
      const cv::v_float32 vk1[3] = {cv::vx_setall_f32(k1[0]), cv::vx_setall_f32(k1[1]), cv::vx_setall_f32(k1[2])};
      for (; x <= bgr.cols - cv::v_float32::nlanes; x += cv::v_float32::nlanes) {
        cv::v_float32 cb, cg, cr;
        cv::v_load_deinterleave(cf + 3 * x, cb, cg, cr);
        const cv::v_float32 mean = (cb + cg + cr) * third;
        const cv::v_float32 a0 = (cb - mean - vm0[0]) * vk0[0], b0 = (cg - mean - vm0[1]) * vk0[1],
                            c0 = (cr - mean - vm0[2]) * vk0[2];
        const cv::v_float32 a1 = (cb - vm1[0]) * vk1[0], b1 = (cg - vm1[1]) * vk1[1], c1 = (cr - vm1[2]) * vk1[2];
        cv::v_store(s0 + x, cv::v_sqrt(a0 * a0 + b0 * b0 + c0 * c0));
        cv::v_store(s1 + x, cv::v_sqrt(a1 * a1 + b1 * b1 + c1 * c1));
      }
#endif
      for (; x < bgr.cols; ++x) {
        const cv::Vec3f h = chromaOf(c[x]);
        const float a0 = (h[0] - m0[0]) * k0[0], b0 = (h[1] - m0[1]) * k0[1], c0 = (h[2] - m0[2]) * k0[2];
        const float a1 = (c[x][0] - m1[0]) * k1[0], b1 = (c[x][1] - m1[1]) * k1[1], c1 = (c[x][2] - m1[2]) * k1[2];
        s0[x] = std::sqrt(a0 * a0 + b0 * b0 + c0 * c0);
        s1[x] = std::sqrt(a1 * a1 + b1 * b1 + c1 * c1);
      }
      out.row_max[0][y] = rowMax(s0, bgr.cols);
      out.row_max[1][y] = rowMax(s1, bgr.cols);
    }
  });
}

void requireValid(const WaterContrastConfig& config, const char* who) {
  const auto problems = config.validate();
  if (!problems.empty()) throw std::invalid_argument(std::string(who) + ": " + problems.front());
}

}  // namespace

WaterContrast measureWaterContrast(const cv::Mat& bgr, const WaterContrastConfig& config, int threads) {
  requireBgr8(bgr, "measureWaterContrast");
  requireValid(config, "measureWaterContrast");
  WaterContrast out;
  // The water: median of a shrunken copy, grown back smoothly.
  const cv::Size small(std::max(kMedianCells, static_cast<int>(std::lround(bgr.cols * config.background_scale))),
                       std::max(kMedianCells, static_cast<int>(std::lround(bgr.rows * config.background_scale))));
  cv::Mat shrunk = shrinkByArea(bgr, small);
  cv::medianBlur(shrunk, shrunk, kMedianCells);
  cv::resize(shrunk, out.water, bgr.size(), 0, 0, cv::INTER_LINEAR);
  measureAgainstWater(bgr, config, nullptr, threads, out);
  return out;
}

WaterContrast contrastAgainst(const cv::Mat& bgr, const cv::Mat& water, const ContrastStats& stats,
                              const WaterContrastConfig& config) {
  requireBgr8(bgr, "contrastAgainst");
  requireBgr8(water, "contrastAgainst (water)");
  requireValid(config, "contrastAgainst");
  if (water.size() != bgr.size()) throw std::invalid_argument("contrastAgainst: image and water sizes differ");
  WaterContrast out;
  out.water = water;
  measureAgainstWater(bgr, config, &stats, 1, out);
  return out;
}

}  // namespace underwater_stereo
