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

/// Below this many values std::nth_element is faster than clearing the radix select's 65536 bins.
constexpr std::size_t kRadixSelectFrom = 16384;

/// The element of `v` at v.size() / 2 in sorted order, as std::nth_element gives it (from kRadixSelectFrom
/// values on), found by a radix select
/// over the floats' order-preserving bit patterns: a histogram of the upper 16 bits, then the one bin that holds
/// the median sorted. (nth_element over the ~36 000 samples of a 960x600 frame, twelve times, was a tenth of the
/// colour stage.) The values must not be NaN.
float medianOf(std::vector<float>& v) {
  if (v.size() < kRadixSelectFrom) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  }
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

/// The frame's spread of chroma and contrast, on every step-th pixel of every step-th row (the two spreads on
/// `threads` threads).
ContrastStats statsOf(const cv::Mat& bgr, const cv::Mat& water, const ContrastOf& contrast, int threads,
                      int step = kStatsStep) {
  std::array<std::vector<float>, 3> chroma, full;
  const std::size_t samples = std::size_t((bgr.rows + step - 1) / step) * ((bgr.cols + step - 1) / step);
  for (int k = 0; k < 3; ++k) {
    chroma[k].reserve(samples);
    full[k].reserve(samples);
  }
  for (int y = 0; y < bgr.rows; y += step) {
    const auto* i = bgr.ptr<cv::Vec3b>(y);
    const auto* w = water.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; x += step) {
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

cv::Vec3f contrastOf(const cv::Vec3f& colour, const cv::Vec3b& water, double offset) {
  cv::Vec3f c;
  for (int k = 0; k < 3; ++k) c[k] = static_cast<float>(std::log((colour[k] + offset) / (water[k] + offset)));
  return c;
}

std::vector<std::string> WaterContrastConfig::validate() const {
  std::vector<std::string> p;
  if (!(background_scale >= 0.005 && background_scale <= 0.5)) p.push_back("water.background_scale must be in [0.005, 0.5]");
  if (!(ratio_offset >= 0.5 && ratio_offset <= 64)) p.push_back("water.ratio_offset must be in [0.5, 64]");
  if (!(object_level >= 0 && object_level <= 1000)) p.push_back("water.object_level must be in [0, 1000] (0: off)");
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

/// Objects are looked for in a view of the frame with about this many pixels per window cell along each side
/// (fine enough to show the rim of an object larger than the window, a few pixels wide).
constexpr int kFineCells = 4;
/// Regions whose hulls cover less than a quarter of a window (in fine pixels) are not left out: the window's
/// median is the water wherever an object covers less than half of it (a quarter leaves room for neighbours).
constexpr double kLeastObjectArea = kMedianCells * kMedianCells * kFineCells * kFineCells / 4.0;
/// The view's spreads are measured on every kFineStatsStep-th pixel of every kFineStatsStep-th row.
constexpr int kFineStatsStep = 2;
/// Beyond this share of the frame the objects cannot be told from the water: the first estimate stays.
constexpr double kMaxObjectShare = 0.5;
/// The fill under objects stops when no cell changes by more than this (grey levels), or after kFillSweeps
/// sweeps; each sweep moves a cell kOverRelaxation times the way to its neighbours' mean (successive
/// over-relaxation: the same fill in a fraction of Gauss-Seidel's sweeps).
constexpr float kFillTolerance = 0.25f;
constexpr int kFillSweeps = 500;
constexpr float kOverRelaxation = 1.7f;
/// Rounds of finding objects against the water estimated without those found before.
constexpr int kObjectRounds = 3;
/// The fill under an object starts from the median of at least this many water cells around each of its cells
/// (the window grows until it has them).
constexpr int kMinWaterCells = 5;

/// The pixels of `image` (the frame at about kFineCells pixels per window cell) that lie under an object: where they
/// stand out from the water estimate `water` (of the image's size) at config.object_level (in the spreads
/// `saliencies` measures in),
/// each region large enough to be a window's median taken with its convex hull
/// (an object larger than the window stands out only at its rim). Empty when they would cover more than
/// kMaxObjectShare of the frame.
cv::Mat objectsAgainst(const cv::Mat& image, const cv::Mat& water, const ContrastOf& contrast,
                       const Saliencies& saliencies, const WaterContrastConfig& config) {
  const cv::Size fine = image.size();
  cv::Mat salient(fine, CV_8UC1);
  for (int y = 0; y < fine.height; ++y) {
    const auto* i = image.ptr<cv::Vec3b>(y);
    const auto* w = water.ptr<cv::Vec3b>(y);
    auto* s = salient.ptr<std::uint8_t>(y);
    for (int x = 0; x < fine.width; ++x) {
      float chroma, full;
      saliencies(contrast(i[x], w[x]), chroma, full);
      s[x] = std::max(chroma, full) > config.object_level ? 255 : 0;
    }
  }
  std::vector<std::vector<cv::Point>> regions;
  cv::findContours(salient, regions, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  cv::Mat objects = cv::Mat::zeros(fine, CV_8UC1);
  std::vector<cv::Point> hull;
  for (const auto& region : regions) {
    cv::convexHull(region, hull);
    if (cv::contourArea(hull) < kLeastObjectArea) continue;
    cv::fillConvexPoly(objects, hull, 255);
  }
  if (cv::countNonZero(objects) > kMaxObjectShare * static_cast<double>(objects.total())) return cv::Mat();
  return objects;
}

/// `medians` (the median of `cells` over kMedianCells windows) with the objects left out: a water cell whose
/// window holds object cells takes the per-channel median of the water cells in it; the cells under objects
/// are then filled smoothly from the water around them (each the mean of its neighbours, by over-relaxed sweeps
/// from the median of the nearest kMinWaterCells water cells; a steady gradient of the water carries on under
/// the object, and an object cut by the border is filled from its other sides).
cv::Mat waterAround(const cv::Mat& cells, const cv::Mat& medians, const cv::Mat& objects) {
  cv::Mat out = medians.clone();
  cv::Mat near;
  cv::dilate(objects, near, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(kMedianCells, kMedianCells)));
  std::array<std::vector<std::uint8_t>, 3> values;
  const int largest = std::max(cells.rows, cells.cols);
  for (int y = 0; y < cells.rows; ++y) {
    for (int x = 0; x < cells.cols; ++x) {
      if (!near.at<std::uint8_t>(y, x)) continue;
      const std::size_t needed = objects.at<std::uint8_t>(y, x) ? kMinWaterCells : 1;
      for (int r = kMedianCells / 2; r <= largest; ++r) {
        for (auto& v : values) v.clear();
        for (int v = std::max(0, y - r); v <= std::min(cells.rows - 1, y + r); ++v) {
          for (int u = std::max(0, x - r); u <= std::min(cells.cols - 1, x + r); ++u) {
            if (objects.at<std::uint8_t>(v, u)) continue;
            const cv::Vec3b& c = cells.at<cv::Vec3b>(v, u);
            for (int k = 0; k < 3; ++k) values[k].push_back(c[k]);
          }
        }
        if (values[0].size() >= needed) break;
      }
      if (values[0].empty()) continue;
      for (int k = 0; k < 3; ++k) {
        auto middle = values[k].begin() + values[k].size() / 2;
        std::nth_element(values[k].begin(), middle, values[k].end());
        out.at<cv::Vec3b>(y, x)[k] = *middle;
      }
    }
  }
  cv::Mat smooth;
  out.convertTo(smooth, CV_32FC3);
  for (int sweep = 0; sweep < kFillSweeps; ++sweep) {
    float change = 0.f;
    for (int y = 0; y < cells.rows; ++y) {
      for (int x = 0; x < cells.cols; ++x) {
        if (!objects.at<std::uint8_t>(y, x)) continue;
        cv::Vec3f sum(0, 0, 0);
        int n = 0;
        for (const cv::Point d : {cv::Point(-1, 0), cv::Point(1, 0), cv::Point(0, -1), cv::Point(0, 1)}) {
          const cv::Point q(x + d.x, y + d.y);
          if (q.x < 0 || q.y < 0 || q.x >= cells.cols || q.y >= cells.rows) continue;
          sum += smooth.at<cv::Vec3f>(q);
          ++n;
        }
        cv::Vec3f& v = smooth.at<cv::Vec3f>(y, x);
        const cv::Vec3f step = (sum * (1.f / n) - v) * kOverRelaxation;
        change = std::max({change, std::abs(step[0]), std::abs(step[1]), std::abs(step[2])});
        v += step;
      }
    }
    if (change < kFillTolerance) break;
  }
  smooth.convertTo(out, CV_8UC3);
  return out;
}

/// The water cells: `medians` (the median of the frame's `cells` over kMedianCells windows) with the objects
/// left out. Each round finds the objects against the last estimate (their rims widen as the water under them
/// clears) and adds them to those found before, until none is added or after kObjectRounds rounds.
cv::Mat waterWithoutObjects(const cv::Mat& bgr, const cv::Mat& cells, const cv::Mat& medians,
                            const WaterContrastConfig& config) {
  // kFineCells pixels per cell along each side, rounded: a whole number of the image's pixels per view pixel where
  // the image allows (OpenCV's area shrink is fastest there: 0.1 against 0.45 ms for 960x600).
  const double per_cell = kFineCells * config.background_scale;
  const cv::Mat image = shrinkByArea(bgr, cv::Size(std::max(1, static_cast<int>(std::lround(bgr.cols * per_cell))),
                                                   std::max(1, static_cast<int>(std::lround(bgr.rows * per_cell)))));
  const ContrastOf contrast(config.ratio_offset);
  cv::Mat water = medians, objects = cv::Mat::zeros(image.size(), CV_8UC1);
  cv::Mat seen;  // the last estimate at the view's size
  cv::resize(water, seen, image.size(), 0, 0, cv::INTER_LINEAR);
  // The frame's spreads against the first estimate serve every round (the water changes only under objects).
  const Saliencies saliencies(statsOf(image, seen, contrast, 1, kFineStatsStep));
  for (int round = 0; round < kObjectRounds; ++round) {
    const cv::Mat found = objectsAgainst(image, seen, contrast, saliencies, config);
    if (found.empty()) break;
    const int before = cv::countNonZero(objects);
    cv::bitwise_or(objects, found, objects);
    if (cv::countNonZero(objects) == before) break;
    cv::Mat share;
    cv::resize(objects, share, cells.size(), 0, 0, cv::INTER_AREA);
    water = waterAround(cells, medians, share > 127);
    cv::resize(water, seen, image.size(), 0, 0, cv::INTER_LINEAR);
  }
  return water;
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
  const Saliencies saliencies(out.stats);
  const cv::Vec3f &m0 = saliencies.m0, &m1 = saliencies.m1, &k0 = saliencies.k0, &k1 = saliencies.k1;
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
      for (; x < bgr.cols; ++x) saliencies(c[x], s0[x], s1[x]);
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
  const cv::Mat cells = shrinkByArea(bgr, small);
  cv::Mat water_cells;
  cv::medianBlur(cells, water_cells, kMedianCells);
  if (config.object_level > 0) water_cells = waterWithoutObjects(bgr, cells, water_cells, config);
  cv::resize(water_cells, out.water, bgr.size(), 0, 0, cv::INTER_LINEAR);
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
