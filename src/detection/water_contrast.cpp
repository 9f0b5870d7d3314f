// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/water_contrast.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {
namespace {

/// Median window over the shrunken image: 5 cells (a cell is 1 / background_scale pixels).
constexpr int kMedianCells = 5;
/// The frame's spread is measured on every kStatsStep-th pixel of every kStatsStep-th row.
constexpr int kStatsStep = 4;

cv::Vec3f channelMedian(std::array<std::vector<float>, 3>& values) {
  cv::Vec3f m;
  for (int c = 0; c < 3; ++c) {
    auto& v = values[c];
    if (v.empty()) return cv::Vec3f(0, 0, 0);
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    m[c] = v[v.size() / 2];
  }
  return m;
}

/// Median and MAD per channel of a CV_32FC3 image, on a sparse grid.
void spreadOf(const cv::Mat& x, cv::Vec3f& median, cv::Vec3f& spread) {
  std::array<std::vector<float>, 3> values;
  for (int y = 0; y < x.rows; y += kStatsStep) {
    const auto* p = x.ptr<cv::Vec3f>(y);
    for (int i = 0; i < x.cols; i += kStatsStep) {
      for (int c = 0; c < 3; ++c) values[c].push_back(p[i][c]);
    }
  }
  median = channelMedian(values);
  for (int c = 0; c < 3; ++c) {
    for (float& v : values[c]) v = std::abs(v - median[c]);
  }
  spread = channelMedian(values);
  for (int c = 0; c < 3; ++c) spread[c] = std::max(spread[c], 1e-3f);
}

/// |(x - median) / spread| per pixel.
cv::Mat normalisedDistance(const cv::Mat& x, const cv::Vec3f& median, const cv::Vec3f& spread) {
  cv::Mat out(x.size(), CV_32FC1);
  const float k0 = 1.f / spread[0], k1 = 1.f / spread[1], k2 = 1.f / spread[2];
  for (int y = 0; y < x.rows; ++y) {
    const auto* p = x.ptr<cv::Vec3f>(y);
    auto* o = out.ptr<float>(y);
    for (int i = 0; i < x.cols; ++i) {
      const float a = (p[i][0] - median[0]) * k0, b = (p[i][1] - median[1]) * k1, c = (p[i][2] - median[2]) * k2;
      o[i] = std::sqrt(a * a + b * b + c * c);
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> WaterContrastConfig::validate() const {
  std::vector<std::string> p;
  if (!(background_scale >= 0.005 && background_scale <= 0.5)) p.push_back("water.background_scale must be in [0.005, 0.5]");
  if (!(ratio_offset >= 0.5 && ratio_offset <= 64)) p.push_back("water.ratio_offset must be in [0.5, 64]");
  return p;
}

namespace {

/// Contrast, chroma and saliency of `out` from its image and water (stats given, or measured when null), in
/// one pass per pixel (OpenCV's per-operation passes over float images cost ~5x more here).
void measureAgainstWater(const cv::Mat& bgr, const WaterContrastConfig& config, const ContrastStats* stats,
                         WaterContrast& out) {
  // log((I + o) / (B + o)) from one table of log(v + o); chroma: minus the mean over the channels.
  std::array<float, 256> log_table;
  for (int v = 0; v < 256; ++v) log_table[v] = std::log(static_cast<float>(v + config.ratio_offset));
  out.contrast.create(bgr.size(), CV_32FC3);
  out.chroma.create(bgr.size(), CV_32FC3);
  for (int y = 0; y < bgr.rows; ++y) {
    const auto* i = bgr.ptr<cv::Vec3b>(y);
    const auto* w = out.water.ptr<cv::Vec3b>(y);
    auto* c = out.contrast.ptr<cv::Vec3f>(y);
    auto* h = out.chroma.ptr<cv::Vec3f>(y);
    for (int x = 0; x < bgr.cols; ++x) {
      const float c0 = log_table[i[x][0]] - log_table[w[x][0]], c1 = log_table[i[x][1]] - log_table[w[x][1]],
                  c2 = log_table[i[x][2]] - log_table[w[x][2]];
      const float mean = (c0 + c1 + c2) * (1.f / 3.f);
      c[x] = cv::Vec3f(c0, c1, c2);
      h[x] = cv::Vec3f(c0 - mean, c1 - mean, c2 - mean);
    }
  }
  if (stats) {
    out.stats = *stats;
  } else {
    spreadOf(out.chroma, out.stats.median[0], out.stats.spread[0]);
    spreadOf(out.contrast, out.stats.median[1], out.stats.spread[1]);
  }
  out.saliency[0] = normalisedDistance(out.chroma, out.stats.median[0], out.stats.spread[0]);
  out.saliency[1] = normalisedDistance(out.contrast, out.stats.median[1], out.stats.spread[1]);
}

void requireValid(const WaterContrastConfig& config, const char* who) {
  const auto problems = config.validate();
  if (!problems.empty()) throw std::invalid_argument(std::string(who) + ": " + problems.front());
}

}  // namespace

WaterContrast measureWaterContrast(const cv::Mat& bgr, const WaterContrastConfig& config) {
  requireBgr8(bgr, "measureWaterContrast");
  requireValid(config, "measureWaterContrast");
  WaterContrast out;
  // The water: median of a shrunken copy, grown back smoothly.
  const cv::Size small(std::max(kMedianCells, static_cast<int>(std::lround(bgr.cols * config.background_scale))),
                       std::max(kMedianCells, static_cast<int>(std::lround(bgr.rows * config.background_scale))));
  cv::Mat shrunk;
  cv::resize(bgr, shrunk, small, 0, 0, cv::INTER_AREA);
  cv::medianBlur(shrunk, shrunk, kMedianCells);
  cv::resize(shrunk, out.water, bgr.size(), 0, 0, cv::INTER_LINEAR);
  measureAgainstWater(bgr, config, nullptr, out);
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
  measureAgainstWater(bgr, config, &stats, out);
  return out;
}

}  // namespace underwater_stereo
