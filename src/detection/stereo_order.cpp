// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/stereo_order.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace underwater_stereo {
namespace {

/// The patch is compared at most this many pixels across (its scale also sets the search's).
constexpr double kMaxPatchPx = 64.0;
/// Rows searched beyond the expected ones, at the compared scale (the scale is at most 1/2; the expected rows come
/// from the calibration); columns: one compared pixel beyond the expected shifts.
constexpr int kRowSlackPx = 3;
/// An object looks swapped when its backward match is this good and better than every forward one by kSwapMargin.
/// Chosen on the validation seeds 60000-60299 and the same pairs swapped (docs/reliability.md, "A pair in the wrong
/// order"): an object's own view correlates with its patch at 0.83-0.98 (quartiles), other places at 0.08-0.48.
constexpr double kMinSwappedCorrelation = 0.8;
constexpr double kSwapMargin = 0.2;

}  // namespace

bool StereoOrder::looksSwapped() const {
  const double rival = forward != kNotCompared ? forward : backward_in_left;
  return rival != kNotCompared && backward >= kMinSwappedCorrelation && backward > rival + kSwapMargin;
}

bool PairOrder::looksSwapped() const { return swapped > 0 && swapped >= silhouettes && 2 * swapped >= objects; }

PairOrder pairOrder(const std::vector<ObjectOrderEvidence>& objects) {
  PairOrder out;
  out.objects = objects.size();
  for (const ObjectOrderEvidence& o : objects) {
    if (o.silhouette) {
      ++out.silhouettes;
    } else if (o.order.looksSwapped()) {
      ++out.swapped;
    }
  }
  return out;
}

StereoOrder compareStereoOrder(const RawFrame& left, const RawFrame& right, const cv::Rect& roi, int min_shift,
                               int max_shift, double row_offset_px) {
  const cv::Rect frame(cv::Point(), left.size());
  if (right.size() != left.size()) throw std::invalid_argument("compareStereoOrder: the frames differ in size");
  if (roi.empty() || (roi & frame) != roi) throw std::invalid_argument("compareStereoOrder: roi outside the frame");
  if (!std::isfinite(row_offset_px)) throw std::invalid_argument("compareStereoOrder: row offset not finite");
  StereoOrder out;
  const int lo = std::max(1, std::min(min_shift, frame.width)), hi = std::max(lo, std::min(max_shift, frame.width));
  const int row_offset = static_cast<int>(std::lround(std::clamp(row_offset_px, -1.0 * frame.height, 1.0 * frame.height)));
  // Rows whose view lies beyond the right image on either side (the cameras' row offset) are left out of the patch
  // on both sides alike: a region touching the top or bottom border is still compared.
  const int offset_rows = std::abs(row_offset);
  const int first_row = std::max(roi.y, offset_rows);
  const int end_row = std::min(roi.y + roi.height, frame.height - offset_rows);
  if (end_row <= first_row) return out;
  const cv::Rect compared(roi.x, first_row, roi.width, end_row - first_row);
  const double scale = std::min(0.5, kMaxPatchPx / std::max(compared.width, compared.height));
  // A region too thin to keep 4 pixels across at this scale says nothing (and would resize to nothing).
  if (cvRound(compared.width * scale) < 4 || cvRound(compared.height * scale) < 4) return out;
  auto grey = [scale](const RawFrame& f, const cv::Rect& r) {
    cv::Mat g;
    cv::resize(f.grey(r), g, cv::Size(), scale, scale, cv::INTER_AREA);
    return g;
  };
  const cv::Mat patch = grey(left, compared);
  cv::Scalar mean, spread;
  cv::meanStdDev(patch, mean, spread);
  if (spread[0] < 1.0) return out;  // a flat patch matches anywhere alike
  // The best match in the part of the right image where the object's view lies `sign` x [lo, hi] columns left of
  // the patch and `sign` x row_offset rows lower (a swapped pair's right image is the left one's, so both are off
  // the other way), +- the slack; `near_slack` columns beyond the smallest shift (0 where the patch is matched with
  // its own image: at a fraction of a compared pixel any patch matches itself).
  const int row_slack = static_cast<int>(std::ceil(kRowSlackPx / scale)), column_slack = static_cast<int>(std::ceil(1 / scale));
  auto best = [&](const RawFrame& image, int sign, int near_slack) {
    const int x0 = sign > 0 ? compared.x - hi : compared.x + lo;
    const int left_slack = sign > 0 ? column_slack : near_slack, right_slack = sign > 0 ? near_slack : column_slack;
    const cv::Rect band = cv::Rect(x0 - left_slack, compared.y + sign * row_offset - row_slack,
                                   hi - lo + compared.width + left_slack + right_slack, compared.height + 2 * row_slack) &
                          frame;
    // Not in the image on this side: a region within lo - column_slack columns of the left border (its view in a pair
    // in order lies beyond the right image), or of the right border for the other side. (The rows always fit: those
    // beyond the image at the row offset were left out of `compared`.)
    if (band.width < compared.width || band.height < compared.height) return StereoOrder::kNotCompared;
    const cv::Mat searched = grey(image, band);
    if (searched.cols < patch.cols || searched.rows < patch.rows) return StereoOrder::kNotCompared;
    cv::Mat score;
    cv::matchTemplate(searched, patch, score, cv::TM_CCOEFF_NORMED);
    double top = -1.0;
    cv::minMaxLoc(score, nullptr, &top);
    return top;
  };
  out.forward = best(right, +1, column_slack);
  out.backward = best(right, -1, column_slack);
  if (out.forward == StereoOrder::kNotCompared) out.backward_in_left = best(left, -1, 0);
  return out;
}

int SwappedPairWatch::add(bool looks_swapped, bool has_objects) {
  if (looks_swapped) {
    const int swapped = ++since_objects_;
    return swapped >= kPairsForWiring ? swapped : 0;
  }
  if (has_objects) since_objects_ = 0;
  return 0;
}

}  // namespace underwater_stereo
