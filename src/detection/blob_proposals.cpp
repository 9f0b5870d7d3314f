// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/blob_proposals.h"

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <optional>
#include <set>
#include <stdexcept>
#include <vector>

#include "underwater_stereo/detection/candidate_finder.h"
#include "underwater_stereo/detection/image_checks.h"
#include "underwater_stereo/detection/work_on_threads.h"

namespace underwater_stereo {
namespace {

/// Opening that removes single-pixel specks of saliency (sensor noise, JPEG blocks) before cutting regions.
constexpr int kOpenPx = 3;
/// Width of the ring of water around a region that its contrast is compared with.
constexpr int kRingPx = 3;

cv::Mat openKernel() { return cv::getStructuringElement(cv::MORPH_RECT, cv::Size(kOpenPx, kOpenPx)); }

/// The pixels of `saliency` above `level`, opened (specks removed): 0/255.
cv::Mat openedCut(const cv::Mat& saliency, double level) {
  cv::Mat mask;
  cv::compare(saliency, level, mask, cv::CMP_GT);
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN, openKernel());
  return mask;
}

/// OpenCV's 8-bit HSV saturation (cvtColor COLOR_BGR2HSV): round(255 (max - min) / max), from the same table.
int saturationOf(const cv::Vec3b& p) {
  static const std::array<int, 256> divide = [] {
    std::array<int, 256> t{};
    for (int v = 1; v < 256; ++v) t[v] = cv::saturate_cast<int>((255 << 12) / (1. * v));
    return t;
  }();
  const int v = std::max({p[0], p[1], p[2]}), diff = v - std::min({p[0], p[1], p[2]});
  return (diff * divide[v] + (1 << 11)) >> 12;
}

/// Sums over a proposal's pixels and over the ring of water around it, in one pass over the images.
struct BlobSums {
  double n = 0, ring_n = 0;
  cv::Vec3d contrast, contrast_sq, ring_contrast, raw, water;
  double saliency = 0, saturation = 0;
};

BlobSums sumsOver(const cv::Mat& bgr, const WaterContrast& wc, const cv::Mat& saliency, const cv::Rect& outer,
                  const cv::Mat& inside, const cv::Mat& ring) {
  // Accumulated in local scalars, not in BlobSums' vectors: the compiler then keeps them in registers (the
  // vectors' members went through memory at every pixel, half of this function's time). Same sums, same order.
  double n = 0, ring_n = 0, saliency_sum = 0, saturation = 0;
  double c0 = 0, c1 = 0, c2 = 0, q0 = 0, q1 = 0, q2 = 0, r0 = 0, r1 = 0, r2 = 0;
  double p0 = 0, p1 = 0, p2 = 0, w0 = 0, w1 = 0, w2 = 0;
  for (int y = 0; y < outer.height; ++y) {
    const auto* in = inside.ptr<std::uint8_t>(y);
    const auto* around = ring.ptr<std::uint8_t>(y);
    const auto* c = wc.contrast.ptr<cv::Vec3f>(outer.y + y) + outer.x;
    const auto* p = bgr.ptr<cv::Vec3b>(outer.y + y) + outer.x;
    const auto* w = wc.water.ptr<cv::Vec3b>(outer.y + y) + outer.x;
    const auto* sal = saliency.ptr<float>(outer.y + y) + outer.x;
    for (int x = 0; x < outer.width; ++x) {
      if (in[x]) {
        n += 1;
        const double a = c[x][0], b = c[x][1], d = c[x][2];
        c0 += a;
        c1 += b;
        c2 += d;
        q0 += a * a;
        q1 += b * b;
        q2 += d * d;
        p0 += p[x][0];
        p1 += p[x][1];
        p2 += p[x][2];
        w0 += w[x][0];
        w1 += w[x][1];
        w2 += w[x][2];
        saliency_sum += sal[x];
        saturation += saturationOf(p[x]);
      } else if (around[x]) {
        ring_n += 1;
        r0 += c[x][0];
        r1 += c[x][1];
        r2 += c[x][2];
      }
    }
  }
  BlobSums s;
  s.n = n;
  s.ring_n = ring_n;
  s.contrast = cv::Vec3d(c0, c1, c2);
  s.contrast_sq = cv::Vec3d(q0, q1, q2);
  s.ring_contrast = cv::Vec3d(r0, r1, r2);
  s.raw = cv::Vec3d(p0, p1, p2);
  s.water = cv::Vec3d(w0, w1, w2);
  s.saliency = saliency_sum;
  s.saturation = saturation;
  return s;
}


/// Channel `c` of a region's mean contrast (or its chroma) in the frame's own spreads of it: how unusual the
/// region is in this frame's water, whatever the water (the saliency's per-channel terms, signed).
float zScore(const cv::Vec3d& value, const ContrastStats& stats, SaliencyKind kind, int c) {
  const int k = static_cast<int>(kind);
  return static_cast<float>((value[c] - stats.median[k][c]) / stats.spread[k][c]);
}

std::vector<float> describe(const cv::Mat& bgr, const WaterContrast& wc, const BlobProposal& b) {
  const cv::Rect frame(0, 0, bgr.cols, bgr.rows);
  const cv::Rect outer = (b.roi + cv::Size(2 * kRingPx, 2 * kRingPx) - cv::Point(kRingPx, kRingPx)) & frame;
  cv::Mat inside = cv::Mat::zeros(outer.size(), CV_8UC1);
  b.mask.copyTo(inside(b.roi - outer.tl()));
  const cv::Mat ring = squareDilation(inside, kRingPx);
  const BlobSums s = sumsOver(bgr, wc, wc.saliency[static_cast<int>(b.kind)], outer, inside, ring);
  const double n = std::max(s.n, 1.0);
  cv::Vec3d f_mean, f_std, r_mean;
  for (int k = 0; k < 3; ++k) {
    f_mean[k] = s.contrast[k] / n;
    f_std[k] = std::sqrt(std::max(s.contrast_sq[k] / n - f_mean[k] * f_mean[k], 0.0));
    r_mean[k] = s.ring_n > 0 ? s.ring_contrast[k] / s.ring_n : f_mean[k];
  }
  const cv::Vec3f c_mean = chromaOf(cv::Vec3f(f_mean));
  const cv::Vec3d raw = s.raw / n, water = s.water / n;
  const double water_sum = water[0] + water[1] + water[2] + 1e-3;
  const double raw_sum = raw[0] + raw[1] + raw[2] + 1e-3;
  std::vector<cv::Point> hull;
  cv::convexHull(b.contour, hull);
  const double hull_area = std::max(cv::contourArea(hull), 1.0);
  const double perimeter = std::max(cv::arcLength(b.contour, true), 1.0);
  // Hue is circular and HSV's mean hue is not: hue enters as the direction of the mean colour's chroma.
  const double hue = std::atan2(std::sqrt(3.0) * (raw[1] - raw[0]), 2 * raw[2] - raw[1] - raw[0]);
  const double image_area = static_cast<double>(bgr.total());
  return {static_cast<float>(f_mean[0]), static_cast<float>(f_mean[1]), static_cast<float>(f_mean[2]),
          c_mean[0], c_mean[1], c_mean[2],
          static_cast<float>(f_mean[0] - r_mean[0]), static_cast<float>(f_mean[1] - r_mean[1]),
          static_cast<float>(f_mean[2] - r_mean[2]),
          static_cast<float>(f_std[0]), static_cast<float>(f_std[1]), static_cast<float>(f_std[2]),
          static_cast<float>(raw[0] / raw_sum), static_cast<float>(raw[1] / raw_sum), static_cast<float>(raw[2] / raw_sum),
          static_cast<float>(std::log(b.area_px / image_area)),
          static_cast<float>(b.area_px / std::max(1, b.roi.area())),
          static_cast<float>(b.roi.width / std::max(1.0, double(b.roi.height))),
          static_cast<float>(b.area_px / hull_area),
          static_cast<float>(4 * M_PI * b.area_px / (perimeter * perimeter)),
          static_cast<float>(std::log(b.level)), static_cast<float>(b.kind == SaliencyKind::kFull ? 1 : 0),
          static_cast<float>(std::log(s.saliency / n + 1)),
          static_cast<float>(s.saturation / n / 255.0), static_cast<float>(raw_sum / (3 * 255.0)),
          static_cast<float>(std::cos(hue)), static_cast<float>(std::sin(hue)),
          static_cast<float>(water[0] / water_sum), static_cast<float>(water[1] / water_sum),
          static_cast<float>(std::log(water_sum / 3 + 1)),
          zScore(c_mean, wc.stats, SaliencyKind::kChroma, 0), zScore(c_mean, wc.stats, SaliencyKind::kChroma, 1),
          zScore(c_mean, wc.stats, SaliencyKind::kChroma, 2), zScore(f_mean, wc.stats, SaliencyKind::kFull, 0),
          zScore(f_mean, wc.stats, SaliencyKind::kFull, 1), zScore(f_mean, wc.stats, SaliencyKind::kFull, 2)};
}

/// A piece is kept when it holds kMinPieceShare-kMaxPieceShare of its region's pixels; the rest of the region (more)
/// only once such a piece was kept: the rest of a region cut into slivers alone is the region again, the rest of one a
/// buoy was cut off is the object the buoy touched (docs/accuracy.md, "The rest of a region is a piece too").
/// 2 %, not 5 % (sessions 27-52): a small object beside or behind a large near one of another colour may hold well
/// under 5 % of their region (a box at 1.1 m behind a panel at 0.5 m). Validation seeds 60000-60299: 1 % and 2 % found
/// the same five objects more (and a slightly longer range tail); 0 % (min_area_px alone) no object more than 2 %, one
/// false detection more and a longer range and position tail (docs/accuracy.md, "Small objects against large ones").
constexpr double kMinPieceShare = 0.02, kMaxPieceShare = 0.8;

/// Where `bgr`'s chromaticity steps (ProposalConfig::piece_step) inside `area` (a rectangle of it): CV_8UC1 0/255 of
/// its size. The gradient of ln(R / G) and ln(B / G) (each channel as ln((I + 4) / 4)) is taken from the pixels around
/// `area` too, as over the whole image. Chromaticity, not brightness: shading, caustics and a lit face change the
/// brightness of one object, while two touching objects of two colours differ in chromaticity even where they are
/// equally bright (docs/accuracy.md, "Touching objects cut where their chromaticity steps"). In fixed point (ln in
/// 1/256ths, Sobel in 16 bits without saturation): a tenth of the time float images took.
cv::Mat stepsIn(const cv::Mat& bgr, const cv::Rect& area, double step) {
  constexpr double kOne = 256;  // ln((255 + 4) / 4) * 256 * 2 (a ratio's range) * 4 (Sobel's largest) fits 16 bits
  static const std::array<std::int16_t, 256> log_table = [] {
    std::array<std::int16_t, 256> t{};
    for (int v = 0; v < 256; ++v) t[v] = static_cast<std::int16_t>(std::lround(kOne * std::log((v + 4.0) / 4.0)));
    return t;
  }();
  const cv::Rect padded = (area + cv::Size(2, 2) - cv::Point(1, 1)) & cv::Rect(cv::Point(), bgr.size());
  cv::Mat log_ratios(padded.size(), CV_16SC2);
  for (int y = 0; y < padded.height; ++y) {
    const std::uint8_t* in = bgr.ptr<std::uint8_t>(padded.y + y) + 3 * padded.x;
    auto* out = log_ratios.ptr<std::int16_t>(y);
    for (int x = 0; x < padded.width; ++x) {
      const int green = log_table[in[3 * x + 1]];
      out[2 * x] = static_cast<std::int16_t>(log_table[in[3 * x + 2]] - green);  // ln R/G
      out[2 * x + 1] = static_cast<std::int16_t>(log_table[in[3 * x]] - green);  // ln B/G
    }
  }
  cv::Mat gx, gy;
  cv::Sobel(log_ratios, gx, CV_16S, 1, 0, 3);
  cv::Sobel(log_ratios, gy, CV_16S, 0, 1, 3);
  const cv::Rect inner = area - padded.tl();
  cv::Mat steps(area.size(), CV_8UC1);
  const double per_pixel = step * 8 * kOne;  // Sobel's weights sum to 8
  const auto limit = static_cast<std::uint32_t>(std::min(per_pixel * per_pixel, 4e9));
  for (int y = 0; y < area.height; ++y) {
    const auto* dx = gx.ptr<std::int16_t>(inner.y + y) + 2 * inner.x;
    const auto* dy = gy.ptr<std::int16_t>(inner.y + y) + 2 * inner.x;
    auto* o = steps.ptr<std::uint8_t>(y);
    for (int x = 0; x < area.width; ++x) {
      std::uint32_t g = 0;
      for (int c = 0; c < 2; ++c) {
        g += static_cast<std::uint32_t>(dx[2 * x + c] * dx[2 * x + c]) + static_cast<std::uint32_t>(dy[2 * x + c] * dy[2 * x + c]);
      }
      o[x] = g > limit ? 255 : 0;
    }
  }
  return steps;
}

/// Component `k` of `labels` (connectedComponents of `b`'s mask less its steps) grown back over the step it was cut
/// along (inside `b`), as a piece; nothing when its outline is under `min_area_px`.
std::optional<BlobProposal> pieceOf(const BlobProposal& b, const cv::Mat& labels, int k, double min_area_px) {
  static const cv::Mat grow = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(5, 5));
  cv::Mat piece = labels == k;
  cv::dilate(piece, piece, grow);
  cv::bitwise_and(piece, b.mask, piece);
  std::vector<cv::Point> outline = largestOutline(piece, b.roi.tl());
  if (outline.empty()) return std::nullopt;
  BlobProposal p;
  p.area_px = cv::contourArea(outline);
  if (p.area_px < min_area_px) return std::nullopt;
  p.roi = cv::boundingRect(outline);
  p.mask = filledOutline(outline, p.roi);
  p.kind = b.kind;
  p.level = b.level;
  p.contour = std::move(outline);
  p.piece = true;
  return p;
}

/// The pieces of `b` that the steps (stepsIn over `area`) cut it into, appended to `out`: those of
/// kMinPieceShare-kMaxPieceShare of its pixels, and once one of them is kept, the rest of it (a larger one).
void addPieces(const BlobProposal& b, const cv::Mat& steps, const cv::Rect& area, double min_area_px,
               std::vector<BlobProposal>& out) {
  cv::Mat inner;
  cv::bitwise_and(b.mask, ~steps(b.roi - area.tl()), inner);
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(inner, labels, stats, centroids, 4, CV_32S);
  const double least = std::max(min_area_px, kMinPieceShare * b.area_px), most = kMaxPieceShare * b.area_px;
  const std::size_t before = out.size();
  int rest = -1;  // the component over `most` (at most one)
  for (int k = 1; k < n; ++k) {
    const double area_px = stats.at<int>(k, cv::CC_STAT_AREA);
    if (area_px > most) rest = k;
    if (area_px < least || area_px > most) continue;
    if (auto p = pieceOf(b, labels, k, min_area_px)) out.push_back(std::move(*p));
  }
  if (rest < 0 || out.size() == before) return;
  if (auto p = pieceOf(b, labels, rest, min_area_px)) out.push_back(std::move(*p));
}

}  // namespace

const std::vector<std::string>& blobFeatureNames() {
  static const std::vector<std::string> names{
      "contrast_b", "contrast_g", "contrast_r", "chroma_b", "chroma_g", "chroma_r", "edge_b", "edge_g", "edge_r",
      "texture_b", "texture_g", "texture_r", "chromaticity_b", "chromaticity_g", "chromaticity_r", "log_area_fraction",
      "fill", "aspect", "solidity", "circularity", "log_level", "full_saliency", "log_saliency", "saturation",
      "brightness", "hue_cos", "hue_sin", "water_chromaticity_b", "water_chromaticity_g", "log_water_brightness",
      "chroma_z_b", "chroma_z_g", "chroma_z_r", "contrast_z_b", "contrast_z_g", "contrast_z_r"};
  return names;
}

std::vector<std::string> ProposalConfig::validate() const {
  std::vector<std::string> p;
  if (levels.empty() || levels.size() > 16) p.push_back("proposals.levels: 1 to 16 levels");
  for (double l : levels) {
    if (!(l > 0 && l <= 1000)) p.push_back("proposals.levels: each in (0, 1000]");
  }
  if (!(min_area_px >= 1 && min_area_px < max_area_px)) p.push_back("proposals: need 1 <= min_area_px < max_area_px");
  if (max_proposals < 1 || max_proposals > 10000) p.push_back("proposals.max_proposals must be in [1, 10000]");
  if (!(piece_step >= 0 && piece_step <= 10)) p.push_back("proposals.piece_step must be in [0, 10]");
  return p;
}

cv::Mat salientMask(const WaterContrast& contrast, SaliencyKind kind, double level) {
  return openedCut(contrast.saliency[static_cast<int>(kind)], level);
}

cv::Mat salientMask(const WaterContrast& contrast, SaliencyKind kind, double level, const cv::Rect& band) {
  const cv::Mat& saliency = contrast.saliency[static_cast<int>(kind)];
  if (band.empty() || (band & cv::Rect(cv::Point(), saliency.size())) != band) {
    throw std::invalid_argument("salientMask: the band must be a non-empty part of the frame");
  }
  return openedCut(saliency(band), level);
}

cv::Rect salientBand(const WaterContrast& contrast, SaliencyKind kind, double level) {
  const cv::Mat& saliency = contrast.saliency[static_cast<int>(kind)];
  const std::vector<float>& row_max = contrast.row_max[static_cast<int>(kind)];
  if (static_cast<int>(row_max.size()) != saliency.rows) return cv::Rect(cv::Point(), saliency.size());
  int first = -1, last = -1;
  for (int y = 0; y < saliency.rows; ++y) {
    if (row_max[y] > level) {
      if (first < 0) first = y;
      last = y;
    }
  }
  if (first < 0) return {};
  // kOpenPx rows of nothing on either side: the opening there (and so the mask's contours) is what it is in the
  // whole frame.
  first = std::max(0, first - kOpenPx);
  last = std::min(saliency.rows - 1, last + kOpenPx);
  return cv::Rect(0, first, saliency.cols, last - first + 1);
}

cv::Mat squareDilation(const cv::Mat& mask, int radius) {
  CV_Assert(mask.type() == CV_8UC1 && radius >= 0);
  const int side = 2 * radius + 1;
  // The largest of `side` rows (or of `side` shifted copies of one row) at every pixel, several at a time.
  std::vector<const std::uint8_t*> rows(side);
  const auto maxOf = [&rows, side](std::uint8_t* out, int n) {
    int x = 0;
#if CV_SIMD
    for (; x <= n - cv::v_uint8::nlanes; x += cv::v_uint8::nlanes) {
      cv::v_uint8 m = cv::vx_load(rows[0] + x);
      for (int k = 1; k < side; ++k) m = cv::v_max(m, cv::vx_load(rows[k] + x));
      cv::v_store(out + x, m);
    }
#endif
    for (; x < n; ++x) {
      std::uint8_t m = rows[0][x];
      for (int k = 1; k < side; ++k) m = std::max(m, rows[k][x]);
      out[x] = m;
    }
  };
  cv::Mat across(mask.rows + 2 * radius, mask.cols, CV_8UC1, cv::Scalar(0));
  std::vector<std::uint8_t> padded(mask.cols + 2 * radius, 0);
  for (int y = 0; y < mask.rows; ++y) {
    std::copy_n(mask.ptr<std::uint8_t>(y), mask.cols, padded.begin() + radius);
    for (int k = 0; k < side; ++k) rows[k] = padded.data() + k;
    maxOf(across.ptr<std::uint8_t>(y + radius), mask.cols);
  }
  cv::Mat grown(mask.size(), CV_8UC1);
  for (int y = 0; y < mask.rows; ++y) {
    for (int k = 0; k < side; ++k) rows[k] = across.ptr<std::uint8_t>(y + k);
    maxOf(grown.ptr<std::uint8_t>(y), mask.cols);
  }
  return grown;
}

cv::Mat featureRows(const std::vector<BlobProposal>& regions) {
  cv::Mat rows(static_cast<int>(regions.size()), kBlobFeatureCount, CV_32F);
  for (int i = 0; i < rows.rows; ++i) std::copy(regions[i].features.begin(), regions[i].features.end(), rows.ptr<float>(i));
  return rows;
}

std::vector<BlobProposal> cutIntoPieces(const cv::Mat& bgr, const WaterContrast& contrast,
                                        const std::vector<const BlobProposal*>& regions, const ProposalConfig& config) {
  requireBgr8(bgr, "cutIntoPieces");
  if (contrast.contrast.size() != bgr.size()) throw std::invalid_argument("cutIntoPieces: contrast and image sizes differ");
  if (!(config.piece_step > 0)) return {};  // 0: never (NaN too: validate() refuses it)
  const double min_region = kPieceRegionAreas * config.min_area_px;
  // The steps over each group of overlapping regions' boxes (views of one object at several levels share theirs).
  std::vector<cv::Rect> areas;
  for (const BlobProposal* b : regions) {
    if (b->area_px < min_region) continue;
    cv::Rect grown = b->roi;
    for (auto it = areas.begin(); it != areas.end();) {
      if ((*it & grown).empty()) {
        ++it;
      } else {
        grown |= *it;
        areas.erase(it);
        it = areas.begin();  // the grown box may now meet one passed over
      }
    }
    areas.push_back(grown);
  }
  std::vector<cv::Mat> steps;
  for (const cv::Rect& area : areas) steps.push_back(stepsIn(bgr, area, config.piece_step));
  std::vector<BlobProposal> pieces;
  std::set<std::array<int, 4>> seen;
  for (const BlobProposal* b : regions) {
    if (b->area_px < min_region) continue;
    const auto area = std::find_if(areas.begin(), areas.end(), [&](const cv::Rect& r) { return (r & b->roi) == b->roi; });
    std::vector<BlobProposal> mine;
    addPieces(*b, steps[area - areas.begin()], *area, config.min_area_px, mine);
    for (BlobProposal& p : mine) {
      if (!seen.insert({p.roi.x, p.roi.y, p.roi.width, p.roi.height}).second) continue;
      p.features = describe(bgr, contrast, p);
      pieces.push_back(std::move(p));
    }
  }
  return pieces;
}

std::vector<BlobProposal> proposeBlobs(const cv::Mat& bgr, const WaterContrast& contrast, const ProposalConfig& config,
                                       int threads) {
  requireBgr8(bgr, "proposeBlobs");
  if (contrast.contrast.size() != bgr.size()) throw std::invalid_argument("proposeBlobs: contrast and image sizes differ");
  const auto problems = config.validate();
  if (!problems.empty()) throw std::invalid_argument("proposeBlobs: " + problems.front());
  // Each (saliency, level) cut on its own (in parallel), then in that order: the same proposals whichever
  // thread cut them.
  const int levels = static_cast<int>(config.levels.size());
  std::vector<std::vector<BlobProposal>> cuts(2 * levels);
  workOnThreads(2 * levels, threads, [&](int k) {
    const SaliencyKind kind = k < levels ? SaliencyKind::kChroma : SaliencyKind::kFull;
    const double level = config.levels[k % levels];
    std::vector<std::vector<cv::Point>> contours;
    const cv::Rect band = salientBand(contrast, kind, level);
    if (!band.empty()) {
      cv::findContours(salientMask(contrast, kind, level, band), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE,
                       band.tl());
    }
    for (auto& contour : contours) {
      const double area = cv::contourArea(contour);
      if (area < config.min_area_px || area > config.max_area_px || contour.size() < 3) continue;
      BlobProposal b;
      b.roi = cv::boundingRect(contour);
      b.mask = filledOutline(contour, b.roi);
      b.area_px = area;
      b.kind = kind;
      b.level = level;
      b.contour = std::move(contour);
      cuts[k].push_back(std::move(b));
    }
  });
  std::vector<BlobProposal> out;
  for (auto& cut : cuts) std::move(cut.begin(), cut.end(), std::back_inserter(out));
  if (out.size() > static_cast<std::size_t>(config.max_proposals)) {
    // The most salient (highest level, then largest) first.
    std::stable_sort(out.begin(), out.end(), [](const BlobProposal& a, const BlobProposal& b) {
      return a.level != b.level ? a.level > b.level : a.area_px > b.area_px;
    });
    out.resize(config.max_proposals);
  }
  // In blocks of proposals (one index per proposal would make the threads fight over the counter).
  constexpr int kBlock = 16;
  const int n = static_cast<int>(out.size());
  workOnThreads((n + kBlock - 1) / kBlock, threads, [&](int block) {
    for (int i = block * kBlock; i < std::min(n, (block + 1) * kBlock); ++i) out[i].features = describe(bgr, contrast, out[i]);
  });
  return out;
}

}  // namespace underwater_stereo
