// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/area_shrink.h"

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace underwater_stereo {
namespace {

/// One source row's share of one destination row.
struct RowWeight {
  int source, destination;
  float weight;
};

/// The rows' weights as OpenCV's area resize computes them (partial rows at a cell's edges, whole rows
/// inside; the same double arithmetic, rounded to float).
std::vector<RowWeight> rowWeights(int source_rows, int rows) {
  const double scale = 1. / (static_cast<double>(rows) / source_rows);
  std::vector<RowWeight> weights;
  for (int dy = 0; dy < rows; ++dy) {
    const double f1 = dy * scale, f2 = f1 + scale, height = std::min(scale, source_rows - f1);
    const int s2 = std::min(static_cast<int>(std::floor(f2)), source_rows - 1);
    const int s1 = std::min(static_cast<int>(std::ceil(f1)), s2);
    if (s1 - f1 > 1e-3) weights.push_back({s1 - 1, dy, static_cast<float>((s1 - f1) / height)});
    for (int s = s1; s < s2; ++s) weights.push_back({s, dy, static_cast<float>(1.0 / height)});
    if (f2 - s2 > 1e-3) weights.push_back({s2, dy, static_cast<float>(std::min(std::min(f2 - s2, 1.), height) / height)});
  }
  return weights;
}

/// Per channel, the mean of each `cell` pixels of a BGR row: out[3 c + k] for cell c and channel k.
void cellMeans(const std::uint8_t* row, int cells, int cell, float* out) {
  const float inverse = static_cast<float>(1.0 / cell);
  for (int c = 0; c < cells; ++c) {
    const std::uint8_t* p = row + 3 * c * cell;
    unsigned b = 0, g = 0, r = 0;
    int x = 0;
#if CV_SIMD128
    for (; x + 16 <= cell; x += 16) {
      cv::v_uint8x16 vb, vg, vr;
      cv::v_load_deinterleave(p + 3 * x, vb, vg, vr);
      b += cv::v_reduce_sum(vb);
      g += cv::v_reduce_sum(vg);
      r += cv::v_reduce_sum(vr);
    }
#endif
    for (; x < cell; ++x) {
      b += p[3 * x];
      g += p[3 * x + 1];
      r += p[3 * x + 2];
    }
    out[3 * c] = static_cast<float>(b) * inverse;
    out[3 * c + 1] = static_cast<float>(g) * inverse;
    out[3 * c + 2] = static_cast<float>(r) * inverse;
  }
}

}  // namespace

cv::Mat shrinkByArea(const cv::Mat& src, const cv::Size& size) {
  if (src.empty() || size.width <= 0 || size.height <= 0) {
    throw std::invalid_argument("shrinkByArea: need a non-empty image and a positive size");
  }
  const int cell = src.cols / size.width;
  const bool fast = src.type() == CV_8UC3 && cell * size.width == src.cols && (cell & (cell - 1)) == 0 &&
                    size.height < src.rows && src.rows % size.height != 0;
  cv::Mat dst;
  if (!fast) {
    cv::resize(src, dst, size, 0, 0, cv::INTER_AREA);
    return dst;
  }
  const std::vector<RowWeight> weights = rowWeights(src.rows, size.height);
  const int n = 3 * size.width;
  std::vector<float> means(n), sum(n, 0.f);
  dst.create(size, CV_8UC3);
  const auto store = [&](int row) {
    auto* d = dst.ptr<std::uint8_t>(row);
    for (int k = 0; k < n; ++k) d[k] = cv::saturate_cast<std::uint8_t>(sum[k]);
  };
  int row = weights.front().destination;
  for (const RowWeight& w : weights) {
    cellMeans(src.ptr<std::uint8_t>(w.source), size.width, cell, means.data());
    if (w.destination != row) {
      store(row);
      std::fill(sum.begin(), sum.end(), 0.f);
      row = w.destination;
    }
    for (int k = 0; k < n; ++k) sum[k] += w.weight * means[k];
  }
  store(row);
  return dst;
}

}  // namespace underwater_stereo
