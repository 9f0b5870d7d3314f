// SPDX-License-Identifier: BSD-3-Clause
// The arithmetic follows OpenCV 4's modules/calib3d/src/stereosgbm.cpp (computeDisparity3WaySGBM, BSD/Apache
// licensed) step by step, so that every intermediate 16-bit value, every saturation and every tie comes out the
// same; test/sgbm_3way_matcher_test.cpp checks the result against cv::StereoSGBM pixel by pixel.
#include "underwater_stereo/detection/sgbm_3way_matcher.h"

// The AVX2 matcher exists only where AVX2 can: x86-64. Elsewhere (ARM64 Jetsons) compute() is OpenCV's matcher.
#if defined(__x86_64__)
#define UWS_SGBM_AVX2 1
#include <immintrin.h>
#endif

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {
namespace {

using Cost = std::int16_t;
constexpr int kLanes = 16;     ///< 16-bit costs per AVX2 register
constexpr int kStripes = 4;    ///< OpenCV matches in four row stripes, each with its own top-down path
constexpr int kDispScale = 16; ///< disparities in 1/16 px
constexpr int kInvalid = -kDispScale;
constexpr int kClip = 15;      ///< preFilterCap 0: OpenCV clips the Sobel response to +-15

#ifdef UWS_SGBM_AVX2

[[gnu::target("avx2")]] inline __m256i load(const Cost* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
[[gnu::target("avx2")]] inline void store(Cost* p, __m256i v) { _mm256_storeu_si256(reinterpret_cast<__m256i*>(p), v); }

/// r[i] = a[i-1], r[0] = before[15].
[[gnu::target("avx2")]] inline __m256i previousLane(__m256i a, __m256i before) {
  return _mm256_alignr_epi8(a, _mm256_permute2x128_si256(before, a, 0x21), 14);
}
/// r[i] = a[i+1], r[15] = after[0].
[[gnu::target("avx2")]] inline __m256i nextLane(__m256i a, __m256i after) {
  return _mm256_alignr_epi8(_mm256_permute2x128_si256(a, after, 0x21), a, 2);
}

/// The smallest of the 16 signed lanes, in every lane.
[[gnu::target("avx2")]] inline __m256i broadcastMin(__m256i v) {
  const __m128i bias = _mm_set1_epi16(static_cast<short>(0x8000));
  const __m128i m = _mm_min_epi16(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
  return _mm256_broadcastw_epi16(_mm_xor_si128(_mm_minpos_epu16(_mm_xor_si128(m, bias)), bias));
}
[[gnu::target("avx2")]] inline Cost lane0(__m256i v) { return static_cast<Cost>(_mm256_extract_epi16(v, 0)); }

constexpr int kMaxBlocks = kMaxSgbmDisparities / kLanes;  ///< the widest search, in blocks of 16 disparities

/// One step of a path over all disparities, `nb` blocks: out[d] = cost[d] + min(prev[d-1] + P1, prev[d+1] + P1,
/// prev[d], prev_min + P2) - (prev_min + P2) with prev[-1] = prev[D] = SHRT_MAX, in OpenCV's order of saturating
/// 16-bit operations. `min_p2` holds prev_min + P2 in every lane. Returns the lane-wise least of out.
[[gnu::target("avx2")]] inline __m256i pathStep(const __m256i* prev, __m256i* out, const __m256i* cost, __m256i min_p2,
                                                __m256i p1, int nb) {
  const __m256i border = _mm256_set1_epi16(SHRT_MAX);
  __m256i least = border;
  for (int b = 0; b < nb; ++b) {
    const __m256i before = b > 0 ? prev[b - 1] : border, after = b + 1 < nb ? prev[b + 1] : border;
    const __m256i neighbours = _mm256_min_epi16(previousLane(prev[b], before), nextLane(prev[b], after));
    out[b] = _mm256_adds_epi16(
        cost[b],
        _mm256_subs_epi16(_mm256_min_epi16(_mm256_adds_epi16(neighbours, p1), _mm256_min_epi16(prev[b], min_p2)), min_p2));
    least = _mm256_min_epi16(least, out[b]);
  }
  return least;
}

/// One image row as OpenCV's Birchfield-Tomasi pixel cost reads it, in two channels: 0 the horizontal Sobel
/// response clipped to +-kClip plus kClip, 1 the raw grey, both kClip in the first and last column; per channel
/// the smallest and largest of each pixel and the half-way values to its neighbours.
struct PrefilteredRow {
  std::vector<std::uint8_t> value[2], lo[2], hi[2];

  /// `w` columns and 32 bytes of padding (read by 32-byte loads whose upper lanes go unused).
  void resize(int w) {
    for (int c = 0; c < 2; ++c) {
      value[c].resize(w + 32);
      lo[c].resize(w + 32);
      hi[c].resize(w + 32);
    }
  }
};

/// 16 bytes from p as 16-bit lanes.
[[gnu::target("avx2")]] inline __m256i widen(const std::uint8_t* p) {
  return _mm256_cvtepu8_epi16(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}

/// floor((a + b) / 2) per byte.
[[gnu::target("avx2")]] inline __m256i halfWay(__m256i a, __m256i b) {
  return _mm256_sub_epi8(_mm256_avg_epu8(a, b), _mm256_and_si256(_mm256_xor_si256(a, b), _mm256_set1_epi8(1)));
}

/// Row y of `image` (CV_8UC1, as wide as `out`).
[[gnu::target("avx2")]] void prefilter(const cv::Mat& image, int y, PrefilteredRow& out) {
  const int w = image.cols;
  const std::uint8_t* r = image.ptr<std::uint8_t>(y);
  const std::uint8_t* n = image.ptr<std::uint8_t>(y > 0 ? y - 1 : y);
  const std::uint8_t* s = image.ptr<std::uint8_t>(y < image.rows - 1 ? y + 1 : y);
  std::uint8_t* sobel = out.value[0].data();
  std::uint8_t* raw = out.value[1].data();
  auto sobelAt = [&](int x) {
    const int g = (r[x + 1] - r[x - 1]) * 2 + n[x + 1] - n[x - 1] + s[x + 1] - s[x - 1];
    return static_cast<std::uint8_t>(std::clamp(g, -kClip, kClip) + kClip);
  };
  int x = 1;
  const __m256i clip = _mm256_set1_epi16(kClip), minus_clip = _mm256_set1_epi16(-kClip);
  for (; x + kLanes + 1 <= w - 1; x += kLanes) {
    const __m256i g = _mm256_add_epi16(
        _mm256_add_epi16(_mm256_slli_epi16(_mm256_sub_epi16(widen(r + x + 1), widen(r + x - 1)), 1),
                         _mm256_sub_epi16(widen(n + x + 1), widen(n + x - 1))),
        _mm256_sub_epi16(widen(s + x + 1), widen(s + x - 1)));
    const __m256i clipped = _mm256_add_epi16(_mm256_min_epi16(_mm256_max_epi16(g, minus_clip), clip), clip);
    const __m256i packed = _mm256_permute4x64_epi64(_mm256_packus_epi16(clipped, clipped), 0x08);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(sobel + x), _mm256_castsi256_si128(packed));
  }
  for (; x < w - 1; ++x) sobel[x] = sobelAt(x);
  std::copy(r + 1, r + w - 1, raw + 1);
  sobel[0] = sobel[w - 1] = raw[0] = raw[w - 1] = kClip;
  for (int c = 0; c < 2; ++c) {
    const std::uint8_t* v = out.value[c].data();
    std::uint8_t* lo = out.lo[c].data();
    std::uint8_t* hi = out.hi[c].data();
    auto scalarAt = [&](int i) {
      const int vl = i > 0 ? (v[i] + v[i - 1]) / 2 : v[i], vr = i < w - 1 ? (v[i] + v[i + 1]) / 2 : v[i];
      lo[i] = static_cast<std::uint8_t>(std::min({vl, vr, static_cast<int>(v[i])}));
      hi[i] = static_cast<std::uint8_t>(std::max({vl, vr, static_cast<int>(v[i])}));
    };
    scalarAt(0);
    int i = 1;
    for (; i + 32 <= w - 1; i += 32) {
      const __m256i mid = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v + i));
      const __m256i vl = halfWay(mid, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v + i - 1)));
      const __m256i vr = halfWay(mid, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(v + i + 1)));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(lo + i), _mm256_min_epu8(_mm256_min_epu8(vl, vr), mid));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(hi + i), _mm256_max_epu8(_mm256_max_epu8(vl, vr), mid));
    }
    for (; i < w; ++i) scalarAt(i);
  }
}

/// One stripe of OpenCV's 3WAY matcher with its buffers (calcPixelCostBT, getRawMatchingCost and
/// SGBM3WayMainLoop::impl).
class StripeMatcher {
 public:
  StripeMatcher(const cv::Mat& left, const cv::Mat& right, const SgbmParams& p)
      : left_(left), right_(right), p_(p), w_(left.cols), h_(left.rows), d_(p.num_disparities), blocks_(d_ / kLanes),
        w1_(w_ - d_), half_(p.block_size / 2), hsum_rows_(2 * half_ + 2),
        uniqueness_reciprocal_(((std::uint64_t{1} << 32) + 99 - p.uniqueness_ratio) / (100 - p.uniqueness_ratio)) {}

  /// Matches rows [start, end) and writes row y to row y + shift of `out` where that lies in [out_begin, out_end).
  [[gnu::target("avx2")]] void run(int start, int end, int shift, int out_begin, int out_end, cv::Mat& out) {
    const std::size_t line = static_cast<std::size_t>(w1_) * d_;
    cost_.assign(line, cv::saturate_cast<Cost>(p_.p2));  // OpenCV adds P2 to every cost once: it cancels in the paths
    hsum_.assign(line * hsum_rows_, 0);
    pixel_costs_.assign(static_cast<std::size_t>(2 * half_ + 2) * d_, 0);
    horizontal_.assign(line + d_, 0);
    vertical_.assign(line + d_, 0);
    vertical_min_.assign(w1_ + 1, 0);
    disp2_cost_.resize(w_);
    disp2_.resize(w_);
    row_.resize(w_);
    left_row_.resize(w_);
    right_row_.resize(w_);
    for (int y = start; y < end; ++y) {
      switch (blocks_) {  // up to 64 disparities in registers (their own instantiations), wider ones in memory
        case 1: matchRow<1>(y, start); break;
        case 2: matchRow<2>(y, start); break;
        case 3: matchRow<3>(y, start); break;
        case 4: matchRow<4>(y, start); break;
        default: matchRow<0>(y, start);
      }
      if (y + shift >= out_begin && y + shift < out_end) std::copy(row_.begin(), row_.end(), out.ptr<short>(y + shift));
    }
  }

 private:
  /// Pixel costs of left column d_ + x of the prefiltered rows for disparities 0..d_-1: the Birchfield-Tomasi
  /// cost on the Sobel channel plus a quarter of it on the raw one.
  [[gnu::target("avx2")]] void pixelCost(int x, Cost* out) const {
    const int column = x + d_;
    __m256i u[2], u0[2], u1[2];
    for (int c = 0; c < 2; ++c) {
      u[c] = _mm256_set1_epi8(static_cast<char>(left_row_.value[c][column]));
      u0[c] = _mm256_set1_epi8(static_cast<char>(left_row_.lo[c][column]));
      u1[c] = _mm256_set1_epi8(static_cast<char>(left_row_.hi[c][column]));
    }
    int d0 = 0;
    for (; d0 + 2 * kLanes <= d_; d0 += 2 * kLanes) {
      const __m256i c = costBytes(column - d0 - 2 * kLanes + 1, u, u0, u1);
      store(out + d0, _mm256_cvtepu8_epi16(_mm256_castsi256_si128(c)));
      store(out + d0 + kLanes, _mm256_cvtepu8_epi16(_mm256_extracti128_si256(c, 1)));
    }
    if (d0 < d_) {  // an odd block: the upper half of the 32 disparities from d0 - 16 (reads the rows' padding)
      const __m256i c = costBytes(column - d0 - kLanes + 1, u, u0, u1);
      store(out + d0, _mm256_cvtepu8_epi16(_mm256_extracti128_si256(c, 1)));
    }
  }

  /// The costs (as bytes: Sobel's <= 30 plus a quarter of the raw one's <= 63 fits) of the left pixel whose
  /// channels are broadcast in u, u0 (lo), u1 (hi) against the 32 right columns from i, ascending disparity (the
  /// right columns descending).
  [[gnu::target("avx2")]] __m256i costBytes(int i, const __m256i* u, const __m256i* u0, const __m256i* u1) const {
    __m256i diff[2];
    for (int c = 0; c < 2; ++c) {
      const __m256i v = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(right_row_.value[c].data() + i));
      const __m256i v0 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(right_row_.lo[c].data() + i));
      const __m256i v1 = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(right_row_.hi[c].data() + i));
      const __m256i c0 = _mm256_max_epu8(_mm256_subs_epu8(u[c], v1), _mm256_subs_epu8(v0, u[c]));
      const __m256i c1 = _mm256_max_epu8(_mm256_subs_epu8(v, u1[c]), _mm256_subs_epu8(u0[c], v));
      diff[c] = _mm256_min_epu8(c0, c1);
    }
    const __m256i sum = _mm256_add_epi8(diff[0], _mm256_and_si256(_mm256_srli_epi16(diff[1], 2), _mm256_set1_epi8(0x3F)));
    const __m256i reverse = _mm256_setr_epi8(15, 14, 13, 12, 11, 10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 0, 15, 14, 13, 12, 11, 10, 9,
                                             8, 7, 6, 5, 4, 3, 2, 1, 0);
    return _mm256_permute4x64_epi64(_mm256_shuffle_epi8(sum, reverse), 0x4E);
  }

  /// Pixel costs of column x, kept while the block sums need them (columns x - half_ - 1 .. x + half_).
  Cost* pixelCosts(int x) { return pixel_costs_.data() + static_cast<std::size_t>(x % (2 * half_ + 2)) * d_; }
  Cost* hsumRow(int k) { return hsum_.data() + static_cast<std::size_t>(k % hsum_rows_) * w1_ * d_; }
  Cost* slot(std::vector<Cost>& v, int i) { return v.data() + static_cast<std::size_t>(i) * d_; }

  /// One output row with B blocks of disparities (0: blocks_, more than registers hold): OpenCV's
  /// getRawMatchingCost (image rows k0..k1 enter the block sums of row y, the last completes its costs), the three
  /// paths, the disparity of least summed cost per pixel with uniqueness and sub-pixel refinement, and the
  /// one-map left-right check; result in row_.
  template <int B>
  [[gnu::target("avx2")]] void matchRow(int y, int start) {
    const int k0 = y == start ? start : y + half_, k1 = y == start ? start + half_ : k0;
    for (int k = k0; k < k1; ++k) addBlockSums<B, false>(k, y, start);
    addBlockSums<B, true>(k1, y, start);
    rightToLeft<B>();
    leftRightCheck();
  }

  /// Adds image row k's block sums to cost_ (rows clamped to [start, h)). With kPaths, runs the left-to-right and
  /// top-down paths through each pixel as soon as its cost is complete (into horizontal_ and vertical_).
  template <int B, bool kPaths>
  [[gnu::target("avx2")]] void addBlockSums(int k, int y, int start) {
    constexpr int kSlots = B > 0 ? B : kMaxBlocks;
    const int nb = B > 0 ? B : blocks_;
    Cost* add = hsumRow(std::min(k, h_ - 1));
    const Cost* sub = y > start ? hsumRow(std::max(y - half_ - 1, start)) : nullptr;
    const __m256i scale = _mm256_set1_epi16(static_cast<short>(k == start ? half_ + 1 : 1));
    const __m256i edge = _mm256_set1_epi16(static_cast<short>(half_ + 1));
    const bool fresh = k < h_;  // beyond the last row, the last row's sums again
    if (fresh) {
      prefilter(left_, k, left_row_);
      prefilter(right_, k, right_row_);
      for (int x = 0; x <= half_; ++x) pixelCost(x, pixelCosts(x));
    }
    const __m256i p1 = _mm256_set1_epi16(cv::saturate_cast<Cost>(p_.p1));
    const __m256i p2 = _mm256_set1_epi16(cv::saturate_cast<Cost>(p_.p2));
    __m256i hv[kSlots] = {};  // set at x == 0 of every fresh row before use; zeroed so no compiler has to prove it
    __m256i cost[kSlots], path[kSlots], next[kSlots], top[kSlots];
    for (int b = 0; b < nb; ++b) path[b] = _mm256_setzero_si256();  // the left path starts from 0 costs
    __m256i min_p2 = p2;
    for (int x = 0; x < w1_; ++x) {
      Cost* c = slot(cost_, x);
      Cost* h = add + static_cast<std::size_t>(x) * d_;
      const Cost* s = sub ? sub + static_cast<std::size_t>(x) * d_ : nullptr;
      if (fresh) {
        if (x == 0) {
          for (int b = 0; b < nb; ++b) {
            hv[b] = _mm256_mullo_epi16(load(pixelCosts(0) + b * kLanes), edge);
            for (int j = 1; j <= half_; ++j) hv[b] = _mm256_adds_epi16(hv[b], load(pixelCosts(j) + b * kLanes));
          }
        } else {
          if (x + half_ < w1_) pixelCost(x + half_, pixelCosts(x + half_));
          const Cost* padd = pixelCosts(std::min(x + half_, w1_ - 1));
          const Cost* psub = pixelCosts(std::max(x - half_ - 1, 0));
          for (int b = 0; b < nb; ++b) {
            hv[b] = _mm256_subs_epi16(_mm256_adds_epi16(hv[b], load(padd + b * kLanes)), load(psub + b * kLanes));
          }
        }
        for (int b = 0; b < nb; ++b) {
          const int o = b * kLanes;
          store(h + o, hv[b]);
          cost[b] = s ? _mm256_subs_epi16(_mm256_adds_epi16(load(c + o), hv[b]), load(s + o))
                      : _mm256_adds_epi16(load(c + o), _mm256_mullo_epi16(hv[b], scale));
          store(c + o, cost[b]);
        }
      } else {
        for (int b = 0; b < nb; ++b) {
          const int o = b * kLanes;
          const __m256i sum = _mm256_adds_epi16(load(c + o), load(h + o));
          cost[b] = s ? _mm256_subs_epi16(sum, load(s + o)) : sum;
          store(c + o, cost[b]);
        }
      }
      if (!kPaths) continue;
      // Path slots 1..w1 (slot 0 of the left path stays 0).
      min_p2 = _mm256_adds_epi16(broadcastMin(pathStep(path, next, cost, min_p2, p1, nb)), p2);
      Cost* left = slot(horizontal_, x + 1);
      Cost* vertical = slot(vertical_, x + 1);
      for (int b = 0; b < nb; ++b) {
        store(left + b * kLanes, next[b]);
        path[b] = next[b];
        top[b] = load(vertical + b * kLanes);
      }
      const __m256i top_min_p2 = _mm256_adds_epi16(_mm256_set1_epi16(vertical_min_[x + 1]), p2);
      vertical_min_[x + 1] = lane0(broadcastMin(pathStep(top, next, cost, top_min_p2, p1, nb)));
      for (int b = 0; b < nb; ++b) store(vertical + b * kLanes, next[b]);
    }
  }

  /// The right-to-left path, summed with the other two into the left path's slots, and each pixel's disparity.
  template <int B>
  [[gnu::target("avx2")]] void rightToLeft() {
    constexpr int kSlots = B > 0 ? B : kMaxBlocks;
    const int nb = B > 0 ? B : blocks_;
    std::fill(row_.begin(), row_.end(), static_cast<short>(kInvalid));
    std::fill(disp2_.begin(), disp2_.end(), static_cast<short>(kInvalid));
    std::fill(disp2_cost_.begin(), disp2_cost_.end(), static_cast<Cost>(SHRT_MAX));
    const __m256i p1 = _mm256_set1_epi16(cv::saturate_cast<Cost>(p_.p1));
    const __m256i p2 = _mm256_set1_epi16(cv::saturate_cast<Cost>(p_.p2));
    const __m256i lane_index = _mm256_setr_epi16(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    __m256i cost[kSlots], path[kSlots], next[kSlots];
    for (int b = 0; b < nb; ++b) path[b] = _mm256_setzero_si256();
    __m256i min_p2 = p2;
    for (int i = w1_; i >= 1; --i) {
      const Cost* c = slot(cost_, i - 1);
      Cost* sum = slot(horizontal_, i);
      const Cost* vertical = slot(vertical_, i);
      for (int b = 0; b < nb; ++b) cost[b] = load(c + b * kLanes);
      min_p2 = _mm256_adds_epi16(broadcastMin(pathStep(path, next, cost, min_p2, p1, nb)), p2);
      __m256i least = _mm256_set1_epi16(SHRT_MAX), least_at = _mm256_setzero_si256();
      for (int b = 0; b < nb; ++b) {
        path[b] = next[b];
        next[b] = _mm256_adds_epi16(_mm256_adds_epi16(next[b], load(sum + b * kLanes)), load(vertical + b * kLanes));
        store(sum + b * kLanes, next[b]);
        least = _mm256_min_epi16(least, next[b]);
        least_at = _mm256_blendv_epi8(least_at, _mm256_set1_epi16(static_cast<short>(b * kLanes)), _mm256_cmpeq_epi16(least, next[b]));
      }
      const __m256i min_cost = broadcastMin(least);
      const int best = bestDisparity(least, least_at, min_cost, lane_index);
      const Cost cost = lane0(min_cost);
      // Branch-free from here: whether a pixel is unique follows the image, not a pattern the CPU could predict.
      const bool unique_match = p_.uniqueness_ratio == 0 || unique(next, nb, cost, best, lane_index);
      const int column = i - 1 + d_;
      const int x2 = column - best;  // in [1, w): column >= d_ > best
      const bool take = unique_match && disp2_cost_[x2] > cost;
      disp2_cost_[x2] = take ? cost : disp2_cost_[x2];
      disp2_[x2] = take ? static_cast<short>(best) : disp2_[x2];
      int d = best * kDispScale;
      if (best > 0 && best < d_ - 1) {
        const int denom2 = std::max(sum[best - 1] + sum[best + 1] - 2 * sum[best], 1);
        d += ((sum[best - 1] - sum[best + 1]) * kDispScale + denom2) / (denom2 * 2);
      }
      row_[column] = static_cast<short>(unique_match ? d : kInvalid);
    }
  }

  /// The disparity OpenCV's 8-lane search reports: per lane the last block reaching the lane's least cost, then
  /// among lanes reaching `min_cost` the smallest disparity. 16 lanes hold two of its lanes each (d and d + 8).
  [[gnu::target("avx2")]] static int bestDisparity(__m256i least, __m256i least_at, __m256i min_cost, __m256i lane_index) {
    const __m256i hit = _mm256_cmpeq_epi16(least, min_cost);
    const __m256i at = _mm256_and_si256(hit, _mm256_add_epi16(_mm256_add_epi16(least_at, lane_index), _mm256_set1_epi16(1)));
    const __m128i last = _mm_max_epu16(_mm256_castsi256_si128(at), _mm256_extracti128_si256(at, 1));  // 0: none
    return _mm_cvtsi128_si32(_mm_minpos_epu16(_mm_sub_epi16(last, _mm_set1_epi16(1)))) & 0xFFFF;
  }

  /// Whether no disparity beyond best +- 1 comes within the uniqueness ratio of min_cost.
  [[gnu::target("avx2")]] bool unique(const __m256i* sum, int nb, Cost min_cost, int best, __m256i lane_index) const {
    // (100 * min_cost) / (100 - uniqueness) by a multiplication (exact for these magnitudes), as OpenCV's division.
    const int scaled = 100 * min_cost;
    const int thresh = scaled >= 0 ? static_cast<int>((static_cast<std::uint64_t>(scaled) * uniqueness_reciprocal_) >> 32)
                                   : scaled / (100 - p_.uniqueness_ratio);
    const __m256i limit = _mm256_set1_epi16(static_cast<short>(thresh + 1));
    const __m256i below = _mm256_set1_epi16(static_cast<short>(best - 1)), above = _mm256_set1_epi16(static_cast<short>(best + 1));
    __m256i close = _mm256_setzero_si256();
    for (int b = 0; b < nb; ++b) {
      const __m256i d = _mm256_add_epi16(_mm256_set1_epi16(static_cast<short>(b * kLanes)), lane_index);
      close = _mm256_or_si256(close, _mm256_and_si256(_mm256_cmpgt_epi16(limit, sum[b]),
                                                      _mm256_or_si256(_mm256_cmpgt_epi16(below, d), _mm256_cmpgt_epi16(d, above))));
    }
    return _mm256_testz_si256(close, close);
  }

  /// OpenCV's pseudo left-right check: a disparity whose right pixel (rounded either way) matched back to another
  /// disparity is dropped.
  void leftRightCheck() {
    for (int x = d_; x < w_; ++x) {
      const int d1 = row_[x];
      if (d1 == kInvalid) continue;
      const int down = d1 >> 4, up = (d1 + kDispScale - 1) >> 4;
      const int xd = x - down, xu = x - up;
      if (xd >= 0 && xd < w_ && disp2_[xd] >= 0 && std::abs(disp2_[xd] - down) > p_.disp12_max_diff && xu >= 0 &&
          xu < w_ && disp2_[xu] >= 0 && std::abs(disp2_[xu] - up) > p_.disp12_max_diff) {
        row_[x] = static_cast<short>(kInvalid);
      }
    }
  }

  const cv::Mat& left_;
  const cv::Mat& right_;
  const SgbmParams& p_;
  const int w_, h_, d_, blocks_, w1_, half_, hsum_rows_;
  const std::uint64_t uniqueness_reciprocal_;  ///< 2^32 / (100 - uniqueness_ratio), rounded up
  std::vector<Cost> cost_, hsum_, pixel_costs_, horizontal_, vertical_, vertical_min_, disp2_cost_;
  std::vector<short> disp2_, row_;
  PrefilteredRow left_row_, right_row_;
};

/// OpenCV's 3WAY matcher with AVX2: its four row stripes, each starting its top-down path afresh a few rows above
/// its first output row, then its 3x3 median.
[[gnu::target("avx2")]] cv::Mat computeAvx2(const cv::Mat& left, const cv::Mat& right, const SgbmParams& params) {
  cv::Mat disparity(left.size(), CV_16SC1, cv::Scalar(kInvalid));
  const int h = left.rows;
  const int stripe = static_cast<int>(std::ceil(h / static_cast<double>(kStripes)));
  const int overlap = params.block_size / 2 + 1 + static_cast<int>(std::ceil(0.1 * stripe));
  StripeMatcher matcher(left, right, params);
  for (int s = 0; s < kStripes; ++s) {
    const int start = std::max(std::min(s * stripe - overlap, h), 0), end = std::min((s + 1) * stripe, h);
    // OpenCV finds a stripe's rows at their offset from where the stripe should start: in images so small that
    // it starts clamped at row 0, rows come out shifted (and some never written), and so they do here.
    const int shift = s == 0 ? 0 : s * stripe - overlap - start;
    matcher.run(start, end, shift, s * stripe, end, disparity);
  }
  cv::medianBlur(disparity, disparity, 3);
  return disparity;
}
#endif  // UWS_SGBM_AVX2

}  // namespace

std::vector<std::string> SgbmParams::validate() const {
  std::vector<std::string> p;
  if (num_disparities < kLanes || num_disparities % kLanes != 0 || num_disparities > kMaxSgbmDisparities) {
    p.push_back("num_disparities must be a multiple of 16 in [16, " + std::to_string(kMaxSgbmDisparities) + "], got " +
                std::to_string(num_disparities));
  }
  if (block_size < 3 || block_size > 11 || block_size % 2 == 0) p.push_back("block_size must be odd, 3..11");
  if (p1 <= 0 || p2 <= p1 || p2 > 10000) p.push_back("need 0 < p1 < p2 <= 10000");
  if (uniqueness_ratio < 0 || uniqueness_ratio > 99) p.push_back("uniqueness_ratio must be in [0, 99]");
  if (disp12_max_diff < 1) p.push_back("disp12_max_diff must be 1 or more");
  return p;
}

Sgbm3WayMatcher::Sgbm3WayMatcher(const SgbmParams& params) : params_(params) {
  const auto problems = params_.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems("Sgbm3WayMatcher", problems));
}

bool Sgbm3WayMatcher::accelerated() {
  static const bool avx2 = [] {
    const char* off = std::getenv(kPortableMatcherEnv);
    if (off != nullptr && std::strcmp(off, "") != 0 && std::strcmp(off, "0") != 0) return false;
#ifdef UWS_SGBM_AVX2
    __builtin_cpu_init();  // in case this runs during static initialisation, before libgcc's own
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("sse4.1");
#else
    return false;
#endif
  }();
  return avx2;
}

cv::Mat Sgbm3WayMatcher::compute(const cv::Mat& left, const cv::Mat& right) const {
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1 || left.size() != right.size() ||
      left.cols <= params_.num_disparities + params_.block_size) {
    throw std::invalid_argument("Sgbm3WayMatcher::compute: left and right must be CV_8UC1 of one size, wider than " +
                                std::to_string(params_.num_disparities + params_.block_size) + " px");
  }
#ifdef UWS_SGBM_AVX2
  if (accelerated()) return computeAvx2(left, right, params_);
#endif
  cv::Mat disparity;
  cv::StereoSGBM::create(0, params_.num_disparities, params_.block_size, params_.p1, params_.p2, params_.disp12_max_diff,
                         0, params_.uniqueness_ratio, 0, 0, cv::StereoSGBM::MODE_SGBM_3WAY)
      ->compute(left, right, disparity);
  return disparity;
}

}  // namespace underwater_stereo
