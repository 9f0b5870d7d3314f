// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/roi_stereo_matcher.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/detection/sgbm_3way_matcher.h"
#include "underwater_stereo/detection/stopwatch.h"
#include "underwater_stereo/detection/water_contrast.h"

namespace underwater_stereo {
namespace {

/// Disparity [px] of the workspace's far end (StereoMatchConfig::max_depth_m) for `calibration`: nearer objects have more.
double farEndDisparity(const StereoCalibration& calibration, const StereoMatchConfig& workspace) {
  return calibration.focalPx() * calibration.baselineM() / workspace.max_depth_m;
}

/// Disparities [px] of the workspace's far and near ends for `calibration` (one that validates, with a valid
/// `workspace`: focal length x baseline finite and positive).
std::pair<int, int> disparitiesOf(const StereoCalibration& calibration, const StereoMatchConfig& workspace) {
  const double fb = calibration.focalPx() * calibration.baselineM();
  const int far = static_cast<int>(std::floor(farEndDisparity(calibration, workspace)));
  // A long baseline or lens spreads the workspace over more disparities than block matching searches: its near
  // end is then left out (nearestMatchedDepthM), not the calibration refused.
  return {far, std::min(static_cast<int>(std::ceil(fb / workspace.min_depth_m)), far + kMaxSgbmDisparities - 1)};
}

/// Column profiles of the left and right silhouettes must overlap this much (intersection over union).
constexpr double kMinSilhouetteOverlap = 0.8;
/// Disparities block matching searches beyond the object's expected relief on either side (the silhouette's
/// sub-pixel error, stereo noise).
constexpr int kDisparitySlack = 4;
/// Columns beyond the aligned left silhouette that still count for the right one's centroid.
constexpr int kSilhouetteSlackPx = 3;
/// The silhouette's sub-pixel disparity refined against the left frame's right edge (silhouetteDisparity): steps until
/// one moves it less than kFrameEdgeTolerancePx, at most kMaxFrameEdgeSteps; it may end at most kMaxFrameEdgeMovePx
/// from where it started (the cut takes out the kSilhouetteSlackPx columns let in beyond an outline, worth about as
/// many pixels of disparity). Not tuned.
constexpr int kMaxFrameEdgeSteps = 10;
constexpr double kFrameEdgeTolerancePx = 0.01;
constexpr double kMaxFrameEdgeMovePx = kSilhouetteSlackPx;
/// A right silhouette that runs on beyond the left one's outline (runsOnBeyondOutline): over this many columns, with
/// more than this share of the left one's mean column, where the left frame holds less than this share of it. Not
/// tuned.
constexpr int kRunOnPx = 6;
constexpr double kMaxRunOnShare = 0.5;
/// Columns the left colour mask reaches beyond the roi on either side (leftColourRegion): the columns a run-on is
/// judged in, and a little more.
constexpr int kLeftColourMarginPx = kSilhouetteSlackPx + kRunOnPx + 4;
/// The silhouette's whole-pixel shift is searched on every this many rows.
constexpr int kCoarseRowStep = 4;
/// A roughly convex object is about as deep as it is wide, and the half facing the camera is seen: its surface
/// lies up to relief = d * (extent * kVisibleDepthShare) / f pixels of disparity in front of its outline (a
/// sphere's rim) ...
constexpr double kVisibleDepthShare = 0.5;
/// ... or about relief / 2 either side of the outline's shift (a tilted panel): the window starts this many
/// reliefs before the silhouette's disparity and spans this many reliefs in all.
constexpr double kReliefBehind = 0.5, kReliefSpan = 1.5;
/// SGBM's smoothness penalties per pixel of block area, the values OpenCV's documentation recommends for
/// one channel (P1 = 8 * cn * block^2 for a disparity change of one, P2 = 32 * cn * block^2 for larger ones).
constexpr int kP1PerBlockPixel = 8, kP2PerBlockPixel = 32;
/// Left-right consistency [px]: a disparity the right-to-left check moves by more is refused (object edges).
constexpr int kDisp12MaxDiff = 1;

/// Half-size matches of an object without a silhouette needed to narrow the full-size search around their
/// median (an object's worth of points, as min_cluster_points' default; fewer: the whole workspace is searched).
constexpr int kMinCoarseMatches = 30;
/// A window missed the object's disparity when more than this share of the mask's matched pixels lie within a pixel
/// of its first or last disparity (block matching's best cost at the window's end: the true one lies beyond it).
/// Chosen on the validation seeds between 0.15 and 0.5 (docs/accuracy.md, "A window that missed").
constexpr double kMaxWindowEdgeShare = 0.3;
/// The half-size search of an object without a silhouette also looks beyond the workspace's far end, down to its
/// disparity over this: an object up to this many times farther is seen there (RoiPoints::beyond_far_end), not
/// matched at a wrong disparity inside the workspace.
constexpr int kBeyondFarEndReach = 2;
/// ... where more than this share of its half-size mask's pixels match within kDisparitySlack of their median. Not
/// tuned.
constexpr double kMinFarEndAgreement = 0.5;
/// Block matching searches disparities in blocks of this many (SgbmParams::num_disparities, as OpenCV's
/// numDisparities, must be a multiple).
constexpr int kDisparityStep = 16;

/// Channels summing under this are too dark to tell one chromaticity from another (chromaDistance).
constexpr float kMinChromaSum = 30;

/// The part of a raw frame coloursAround reads: its whole 2x2 cells.
cv::Rect wholeCells(const RawFrame& frame) { return cv::Rect(0, 0, frame.size().width & ~1, frame.size().height & ~1); }

/// A raw frame's colour around each of `at` (raw pixels): its half-size BGR (2x2 cells averaged; a Bayer cell's R, B
/// and mean G, no demosaicing) averaged over 3x3 cells, so about 6x6 pixels. A point outside the frame is not read:
/// its colour stays black, too dark to tell (chromaDistance 0).
std::vector<cv::Vec3f> coloursAround(const RawFrame& frame, const std::vector<cv::Point>& at) {
  std::vector<cv::Vec3f> out(at.size());
  const cv::Rect whole = wholeCells(frame);
  std::vector<cv::Point> inside;
  for (const cv::Point& p : at) {
    if (whole.contains(p)) inside.push_back(p);
  }
  if (inside.empty()) return out;
  cv::Rect box = cv::boundingRect(inside);
  box = cv::Rect((box.x - 4) & ~1, (box.y - 4) & ~1, box.width + 10, box.height + 10) & whole;
  box.width &= ~1;
  box.height &= ~1;
  cv::Mat half;
  cv::blur(frame.halfSizeBgr(box), half, cv::Size(3, 3), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  for (std::size_t i = 0; i < at.size(); ++i) {
    if (!whole.contains(at[i])) continue;
    const int x = std::min((at[i].x - box.x) / 2, half.cols - 1), y = std::min((at[i].y - box.y) / 2, half.rows - 1);
    out[i] = half.at<cv::Vec3b>(y, x);
  }
  return out;
}

/// How far apart two colours' chromaticities lie: half the summed absolute difference of their channels' shares
/// (0 alike, 1 disjoint); 0 when either is too dark to tell (channels summing under kMinChromaSum).
float chromaDistance(const cv::Vec3f& a, const cv::Vec3f& b) {
  const float sa = a[0] + a[1] + a[2], sb = b[0] + b[1] + b[2];
  if (sa < kMinChromaSum || sb < kMinChromaSum) return 0;
  return 0.5F * (std::abs(a[0] / sa - b[0] / sb) + std::abs(a[1] / sa - b[1] / sb) + std::abs(a[2] / sa - b[2] / sb));
}

/// A point's right view does not show the object when it stands out from the water by less than this share of the
/// candidate's saliency level (its left view by at least the level: half allows for the views' differences in
/// shading and for the pixels averaged around each). docs/accuracy.md, "Objects the right camera does not see".
constexpr double kSeenShareOfLevel = 0.5;
/// Fewer compared points than this do not turn an object down: too few to tell a share by.
constexpr int kMinComparedPoints = 10;

/// Whether every spread of `stats` is above 0 (the saliencies divide by them).
bool positiveSpreads(const ContrastStats& stats) {
  for (const cv::Vec3f& spread : stats.spread) {
    for (int k = 0; k < 3; ++k) {
      if (!(spread[k] > 0)) return false;
    }
  }
  return true;
}

/// Counts into `out` the points (raw pixels `left_at` and `right_at` in frames whose read parts are `left_frame` and
/// `right_frame`, their views `left` and `right`: coloursAround) whose left view stands out from the water under it at
/// the candidate's level (compared_points) and whose right view does not reach kSeenShareOfLevel of it against the
/// same water (unseen_points). A point either frame shows outside the part read is not compared (as the colour check).
void countUnseenViews(const std::vector<cv::Point>& left_at, const std::vector<cv::Point>& right_at,
                      const cv::Rect& left_frame, const cv::Rect& right_frame, const std::vector<cv::Vec3f>& left,
                      const std::vector<cv::Vec3f>& right, const ViewAgreement& a, RoiPoints& out) {
  const Saliencies saliency(a.stats);
  auto saliencyOf = [&](const cv::Vec3f& colour, const cv::Vec3b& water) {
    return saliency(contrastOf(colour, water, a.ratio_offset), a.kind);
  };
  for (std::size_t i = 0; i < left_at.size(); ++i) {
    if (!left_frame.contains(left_at[i]) || !right_frame.contains(right_at[i])) continue;
    const cv::Point w(std::min(a.water.cols - 1, static_cast<int>(left_at[i].x * a.water_scale)),
                      std::min(a.water.rows - 1, static_cast<int>(left_at[i].y * a.water_scale)));
    const cv::Vec3b& water = a.water.at<cv::Vec3b>(w);
    if (saliencyOf(left[i], water) < a.level) continue;
    ++out.compared_points;
    if (saliencyOf(right[i], water) < kSeenShareOfLevel * a.level) ++out.unseen_points;
  }
}

/// `n` disparities rounded up to whole steps.
int roundUpToDisparityStep(int n) { return ((n + kDisparityStep - 1) / kDisparityStep) * kDisparityStep; }

/// The share of the mask's matched pixels (those matched into the right band's padding too) whose disparity (CV_16SC1,
/// 1/16 px, from 0 to num_disparities - 1) lies under one pixel from the window's first disparity or within one of
/// its last, whether or not that end is the workspace's own; 0 when none matched. (Session 47's review proposed
/// counting neither the padding nor the workspace's ends, and both ends alike: 2 validation objects worse, none
/// better, docs/accuracy.md.)
double windowEdgeShare(const cv::Mat& mask_band, const cv::Mat& disparity16, int num_disparities) {
  constexpr int kOnePixel = cv::StereoMatcher::DISP_SCALE;
  const int last = (num_disparities - 1) * kOnePixel;
  int matched = 0, at_end = 0;
  for (int v = 0; v < mask_band.rows; ++v) {
    const auto* m = mask_band.ptr<std::uint8_t>(v);
    const auto* d = disparity16.ptr<short>(v);
    for (int u = 0; u < mask_band.cols; ++u) {
      if (!m[u] || d[u] < 0) continue;
      ++matched;
      at_end += d[u] < kOnePixel || d[u] >= last - kOnePixel;
    }
  }
  return matched > 0 ? static_cast<double>(at_end) / matched : 0.0;
}

cv::Matx33d rectifiedIntrinsics(const CameraCalibration& c) {
  return cv::Matx33d(c.P(0, 0), c.P(0, 1), c.P(0, 2), c.P(1, 0), c.P(1, 1), c.P(1, 2), 0, 0, 1);
}

/// Fixed-point maps (integer pixel + 1/32 pixel interpolation index): remap runs about twice as fast as
/// with float maps, and 1/32 px is far below the silhouette's and block matching's precision.
void buildMaps(const CameraCalibration& c, cv::Mat& map_xy, cv::Mat& map_fraction) {
  cv::initUndistortRectifyMap(cv::Mat(c.K), cv::Mat(c.D), cv::Mat(c.R), cv::Mat(rectifiedIntrinsics(c)),
                              cv::Size(c.width, c.height), CV_16SC2, map_xy, map_fraction);
}

/// For each rectified row, the column (fractional) where the raw frame's right edge lies: half a pixel beyond its last
/// column, where a mask ending there fades to half. From the maps' raw x (fixed point: the integer pixel plus
/// (index % 32) / 32), which grows along a row; the rectified row's own end when the raw frame reaches beyond it.
std::vector<double> frameEndColumns(const cv::Mat& map_xy, const cv::Mat& map_fraction, int raw_width) {
  const double edge = raw_width - 0.5;
  auto rawX = [&](int v, int u) {
    return map_xy.at<cv::Vec2s>(v, u)[0] + (map_fraction.at<std::uint16_t>(v, u) % cv::INTER_TAB_SIZE) /
                                              static_cast<double>(cv::INTER_TAB_SIZE);
  };
  std::vector<double> end(map_xy.rows, map_xy.cols - 0.5);
  for (int v = 0; v < map_xy.rows; ++v) {
    int u = map_xy.cols - 1;  // becomes the first column beyond the edge
    if (rawX(v, u) <= edge) continue;
    while (u > 0 && rawX(v, u - 1) > edge) --u;
    if (u == 0) {
      end[v] = -0.5;
      continue;
    }
    const double a = rawX(v, u - 1), b = rawX(v, u);  // a <= edge < b
    end[v] = u - 1 + (edge - a) / (b - a);
  }
  return end;
}

/// Remaps `image` (whose origin is at `origin` of the raw frame) through maps already cut to the output's size.
void remapBand(const cv::Mat& image, cv::Mat& out, const cv::Mat& map_xy, const cv::Mat& map_fraction, const cv::Point& origin,
               int interpolation) {
  const cv::Mat xy = origin == cv::Point() ? map_xy : cv::Mat(map_xy - cv::Scalar(origin.x, origin.y));
  cv::remap(image, out, xy, map_fraction, interpolation, cv::BORDER_CONSTANT, 0);
}

/// Column sums of a mask band (0-255 values, soft edges from bilinear rectification) over the rows `rows`.
std::vector<double> columnProfile(const cv::Mat& band, const cv::Mat& rows) {
  std::vector<double> profile(band.cols, 0.0);
  for (int v = 0; v < band.rows; ++v) {
    if (!rows.at<std::uint8_t>(v)) continue;
    const auto* m = band.ptr<std::uint8_t>(v);
    for (int u = 0; u < band.cols; ++u) profile[u] += m[u];
  }
  return profile;
}

/// First and last column with silhouette in a profile; {-1, -1} if none.
std::pair<int, int> extent(const std::vector<double>& profile) {
  int u0 = -1, u1 = -1;
  for (int u = 0; u < static_cast<int>(profile.size()); ++u) {
    if (profile[u] > 0) {
      if (u0 < 0) u0 = u;
      u1 = u;
    }
  }
  return {u0, u1};
}

/// Whole-pixel shift that best aligns the right profile with the left one (right = left shifted left by d)
/// among [d_lo, d_hi], by intersection over union; -1 when none overlaps kMinSilhouetteOverlap.
int bestShift(const std::vector<double>& left, const std::vector<double>& right, int d_lo, int d_hi) {
  const auto [u0, u1] = extent(left);
  if (u0 < 0) return -1;
  double best = -1.0;
  int best_d = -1;
  for (int d = d_lo; d <= d_hi; ++d) {
    if (u0 - d < 0) break;
    double overlap = 0, norm = 0;
    for (int u = u0; u <= u1; ++u) {
      overlap += std::min(left[u], right[u - d]);
      norm += std::max(left[u], right[u - d]);
    }
    const double score = norm > 0 ? overlap / norm : 0;
    if (score > best) {
      best = score;
      best_d = d;
    }
  }
  return best < kMinSilhouetteOverlap ? -1 : best_d;
}

/// Whether the right profile runs on beyond either end of the left silhouette at `shift` where the left frame does not:
/// over the kRunOnPx columns beyond the slack past that end, the right profile holds more than kMaxRunOnShare of the
/// left silhouette's mean column, and the left frame's whole mask there (`left_around`: with what touches the object)
/// holds less than kMaxRunOnShare of what the right one holds. One object's two silhouettes end alike, or both run
/// on into what touches it; a right one that runs on alone is another object's (a nearer one in the right mask, found
/// at a wrong shift), or this object seen more widely by the right camera than by the left (a nearer one hides part of
/// it from the left camera): the column profiles then overlap at many shifts.
bool runsOnBeyondOutline(const std::vector<double>& left, const std::vector<double>& left_around,
                         const std::vector<double>& right, int shift) {
  const auto [u0, u1] = extent(left);
  if (u0 < 0) return false;
  const double mean_column = std::accumulate(left.begin() + u0, left.begin() + u1 + 1, 0.0) / (u1 - u0 + 1);
  auto at = [](const std::vector<double>& profile, int u) {
    return u >= 0 && u < static_cast<int>(profile.size()) ? profile[u] : 0.0;
  };
  // `end`: the silhouette's first (outward -1) or last (outward 1) column.
  auto runsOn = [&](int end, int outward) {
    double beyond_right = 0, beyond_left = 0;
    for (int k = 0; k < kRunOnPx; ++k) {
      const int beyond = end + outward * (kSilhouetteSlackPx + 1 + k);
      beyond_right += at(right, beyond - shift);
      beyond_left += at(left_around, beyond);
    }
    return beyond_right > kMaxRunOnShare * kRunOnPx * mean_column && beyond_left < kMaxRunOnShare * beyond_right;
  };
  return runsOn(u0, -1) || runsOn(u1, 1);
}

/// The shift refined to sub-pixel: the profiles' centroids, the right one's over the window `shift` aligns
/// with the left silhouette. NaN if either is empty.
double centroidShift(const std::vector<double>& left, const std::vector<double>& right, int shift) {
  const auto [u0, u1] = extent(left);
  if (u0 < 0) return std::numeric_limits<double>::quiet_NaN();
  double left_mass = 0, left_moment = 0, right_mass = 0, right_moment = 0;
  for (int u = u0; u <= u1; ++u) {
    left_mass += left[u];
    left_moment += left[u] * u;
  }
  const int lo = std::max(0, u0 - shift - kSilhouetteSlackPx), hi = std::min<int>(right.size() - 1, u1 - shift + kSilhouetteSlackPx);
  for (int u = lo; u <= hi; ++u) {
    right_mass += right[u];
    right_moment += right[u] * u;
  }
  if (left_mass <= 0 || right_mass <= 0) return std::numeric_limits<double>::quiet_NaN();
  return left_moment / left_mass - right_moment / right_mass;
}

/// Every n-th row of `m` (a header on the same data).
cv::Mat everyNthRow(const cv::Mat& m, int n) { return cv::Mat((m.rows + n - 1) / n, m.cols, m.type(), m.data, m.step[0] * n); }

/// The raw pixels a remap through `map_xy` reads (bilinear: also the next column and row), inside the frame;
/// empty when it reads none. Rectification is smooth and invertible, so the extremes lie on the map's border:
/// only its border is read.
cv::Rect sourceRegion(const cv::Mat& map_xy, const cv::Size& frame) {
  CV_Assert(map_xy.type() == CV_16SC2 && !map_xy.empty());
  int x0 = INT_MAX, x1 = INT_MIN, y0 = INT_MAX, y1 = INT_MIN;
  auto take = [&](const cv::Vec2s& p) {
    x0 = std::min<int>(x0, p[0]);
    x1 = std::max<int>(x1, p[0]);
    y0 = std::min<int>(y0, p[1]);
    y1 = std::max<int>(y1, p[1]);
  };
  for (const int v : {0, map_xy.rows - 1}) {
    const auto* row = map_xy.ptr<cv::Vec2s>(v);
    for (int u = 0; u < map_xy.cols; ++u) take(row[u]);
  }
  for (int v = 0; v < map_xy.rows; ++v) {
    take(map_xy.at<cv::Vec2s>(v, 0));
    take(map_xy.at<cv::Vec2s>(v, map_xy.cols - 1));
  }
  return cv::Rect(cv::Point(x0, y0), cv::Point(x1 + 2, y1 + 2)) & cv::Rect(cv::Point(), frame);
}

/// `band` of a raw frame rectified through the maps, as grey: only the raw pixels it reads are converted. Columns
/// of `band` left of the image (x < 0) repeat its first column (block matching needs its whole disparity range
/// left of every matched pixel).
cv::Mat rectifiedGrey(const RawFrame& frame, const cv::Mat& map_xy, const cv::Mat& map_fraction, const cv::Rect& band) {
  const cv::Rect inside = band & cv::Rect(cv::Point(), map_xy.size());
  const cv::Rect source = inside.empty() ? cv::Rect() : sourceRegion(map_xy(inside), frame.size());
  if (source.empty()) return cv::Mat::zeros(band.size(), CV_8UC1);
  cv::Mat out;
  remapBand(frame.grey(source), out, map_xy(inside), map_fraction(inside), source.tl(), cv::INTER_LINEAR);
  if (inside.x > band.x) cv::copyMakeBorder(out, out, 0, 0, inside.x - band.x, 0, cv::BORDER_REPLICATE);
  return out;
}

}  // namespace

std::vector<std::string> StereoMatchConfig::validate() const {
  std::vector<std::string> p;
  // Each range as detectorTunables() gives it (detector_tunables_test checks that they agree), then their order.
  if (!(min_depth_m >= 0.1 && min_depth_m <= 50)) p.push_back("stereo.min_depth_m must be in [0.1, 50]");
  if (!(max_depth_m >= 0.2 && max_depth_m <= 100)) p.push_back("stereo.max_depth_m must be in [0.2, 100]");
  if (!(min_depth_m < max_depth_m)) {
    p.push_back("stereo: min_depth_m must be under max_depth_m, got " + std::to_string(min_depth_m) + " and " +
                std::to_string(max_depth_m));
  }
  if (block_size < 3 || block_size > 11 || block_size % 2 == 0) p.push_back("stereo.block_size must be odd, in [3, 11]");
  if (uniqueness_ratio < 0 || uniqueness_ratio > 50) p.push_back("stereo.uniqueness_ratio must be in [0, 50]");
  if (margin_px < 0 || margin_px > 200) p.push_back("stereo.margin_px must be in [0, 200]");
  if (erode_px < 0 || erode_px > 50) p.push_back("stereo.erode_px must be in [0, 50]");
  if (max_points < 10 || max_points > 1000000) p.push_back("stereo.max_points must be in [10, 1000000]");
  if (!(max_colour_difference >= 0 && max_colour_difference <= 1)) {
    p.push_back("stereo.max_colour_difference must be in [0, 1]");
  }
  if (!(max_unseen_share >= 0 && max_unseen_share <= 1)) p.push_back("stereo.max_unseen_share must be in [0, 1]");
  return p;
}

RoiStereoMatcher::RoiStereoMatcher(const StereoCalibration& calibration, const StereoMatchConfig& config)
    : calibration_(calibration), config_(config) {
  std::vector<std::string> problems = calibration_.validate();
  const auto config_problems = config_.validate();
  problems.insert(problems.end(), config_problems.begin(), config_problems.end());
  if (!problems.empty()) throw std::invalid_argument(joinProblems("RoiStereoMatcher", problems));
  buildMaps(calibration_.left, left_map_xy_, left_map_fraction_);
  buildMaps(calibration_.right, right_map_xy_, right_map_fraction_);
  left_r_transposed_ = calibration_.left.R.t();
  left_frame_end_ = frameEndColumns(left_map_xy_, left_map_fraction_, calibration_.left.width);
}

cv::Rect RoiStereoMatcher::rectifiedBox(const cv::Rect& raw_roi) const {
  std::vector<cv::Point2f> corners, rectified;
  // Edges, not just corners: distortion bends the box's sides.
  for (int i = 0; i <= 8; ++i) {
    const float fx = raw_roi.x + raw_roi.width * i / 8.0F, fy = raw_roi.y + raw_roi.height * i / 8.0F;
    corners.insert(corners.end(), {{fx, float(raw_roi.y)}, {fx, float(raw_roi.br().y)}, {float(raw_roi.x), fy},
                                   {float(raw_roi.br().x), fy}});
  }
  const CameraCalibration& c = calibration_.left;
  cv::undistortPoints(corners, rectified, cv::Mat(c.K), cv::Mat(c.D), cv::Mat(c.R), cv::Mat(rectifiedIntrinsics(c)));
  return cv::boundingRect(rectified);
}

RoiPoints RoiStereoMatcher::match(const RawFrame& left, const RawFrame& right, const cv::Rect& roi, const cv::Mat& mask,
                                  const cv::Mat& right_colour, const cv::Point& right_colour_origin,
                                  const cv::Mat& left_colour, const ViewAgreement& agreement) const {
  checkMatchInputs(left, right, roi, mask, right_colour, right_colour_origin, left_colour);
  if (!agreement.water.empty() &&
      (agreement.water.type() != CV_8UC3 || !(agreement.water_scale > 0 && agreement.water_scale <= 1) ||
       !(agreement.level > 0) || !positiveSpreads(agreement.stats) || !(agreement.ratio_offset > 0))) {
    throw std::invalid_argument("RoiStereoMatcher::match: the view check needs the water as BGR8 at a scale in (0, 1], "
                                "a level, spreads and ratio offset > 0");
  }
  Stopwatch lap;
  const cv::Rect box = rectifiedBox(roi);
  RoiPoints out;
  // The silhouette's disparity first (masks only, cheap); block matching then searches only a window
  // around it, a fraction of the workspace's range (0.5-5 m: ~400 disparities).
  if (!right_colour.empty()) {
    const cv::Rect left_colour_region = leftColourRegion(roi);
    out.silhouette_disparity =
        left_colour.empty()
            ? silhouetteDisparity(mask, roi, right_colour, right_colour_origin, box)
            : silhouetteDisparity(left_colour(roi - left_colour_region.tl()), roi, right_colour, right_colour_origin, box,
                                  left_colour, left_colour_region.tl());
    // Outside the workspace it is a wrong match (or an object nearer or farther): not trusted.
    if (!inWorkspace(out.silhouette_disparity)) out.silhouette_disparity = std::numeric_limits<double>::quiet_NaN();
  }
  // Without a silhouette the band reaches beyond the workspace's far end, for the half-size search.
  MatchBand band = matchBand(std::isfinite(out.silhouette_disparity) ? disparityWindow(out.silhouette_disparity, box)
                                                                     : workspaceAndBeyond(),
                             box);
  // Nothing to match: a box beyond the image (a far-fetched calibration), too short for a block or too narrow
  // for the disparities searched.
  auto nothingToMatch = [&](const MatchBand& b) {
    const cv::Rect inside = b.left & cv::Rect(cv::Point(), left_map_xy_.size());
    return b.num_disparities < kDisparityStep || b.left.height < config_.block_size || inside.empty() ||
           b.left.width <= b.num_disparities + config_.block_size;
  };
  if (nothingToMatch(band)) {
    out.rectify_ms = lap.lapMs();
    return out;
  }
  cv::Mat left_band, right_band, mask_band;
  auto rectifyBands = [&](const MatchBand& b) {
    left_band = rectifiedGrey(left, left_map_xy_, left_map_fraction_, b.left);
    right_band = rectifiedGrey(right, right_map_xy_, right_map_fraction_, b.right);
    const cv::Rect inside = b.left & cv::Rect(cv::Point(), left_map_xy_.size());
    remapBand(mask, mask_band, left_map_xy_(inside), left_map_fraction_(inside), roi.tl(), cv::INTER_NEAREST);
    if (inside.x > b.left.x) {
      cv::copyMakeBorder(mask_band, mask_band, 0, 0, inside.x - b.left.x, 0, cv::BORDER_CONSTANT, 0);
    }
    if (config_.erode_px > 0) {
      const int side = 2 * config_.erode_px + 1;
      cv::erode(mask_band, mask_band, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(side, side)));
    }
  };
  rectifyBands(band);
  out.mask_pixels = cv::countNonZero(mask_band);
  out.rectify_ms = lap.lapMs();
  if (out.mask_pixels == 0) return out;
  // Without a silhouette, a search at half size over the workspace and beyond (an eighth of the work) sets the
  // window the full-size one searches.
  if (!std::isfinite(out.silhouette_disparity)) {
    const double coarse = coarseDisparity(left_band, right_band, mask_band, band);
    // Farther than the workspace (or no parallax there): nothing in it to match.
    if (coarse < farEndDisparity(calibration_, config_)) {
      out.beyond_far_end = true;
      out.rectify_ms += lap.lapMs();
      return out;
    }
    if (std::isfinite(coarse)) {
      const MatchBand narrow = matchBand(disparityWindow(coarse, box), box);
      if (!nothingToMatch(narrow)) {
        band = narrow;
        rectifyBands(band);
        out.mask_pixels = cv::countNonZero(mask_band);
      }
    }
    out.rectify_ms += lap.lapMs();
  }

  out.searched_disparities = band.num_disparities;
  cv::Mat disparity16 = blockMatch(left_band, right_band, band.num_disparities);
  // A window whose matches pile up at its ends missed the object's disparity (a wrong silhouette or half-size
  // median): the whole workspace is searched instead.
  if (windowEdgeShare(mask_band, disparity16, band.num_disparities) > kMaxWindowEdgeShare) {
    const MatchBand whole = matchBand(disparityWindow(std::numeric_limits<double>::quiet_NaN(), box), box);
    const bool wider = whole.min_disparity < band.min_disparity ||
                       whole.min_disparity + whole.num_disparities > band.min_disparity + band.num_disparities;
    if (wider && !nothingToMatch(whole)) {
      band = whole;
      rectifyBands(band);
      out.mask_pixels = cv::countNonZero(mask_band);
      out.searched_disparities = band.num_disparities;
      out.window_missed = true;
      disparity16 = blockMatch(left_band, right_band, band.num_disparities);
    }
  }
  out.matching_ms = lap.lapMs();
  reproject(left, right, mask_band, disparity16, band, agreement, out);
  out.reprojection_ms = lap.lapMs();
  return out;
}

double RoiStereoMatcher::coarseDisparity(const cv::Mat& left_band, const cv::Mat& right_band, const cv::Mat& mask_band,
                                         const MatchBand& band) const {
  cv::Mat l, r, m;
  cv::resize(left_band, l, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  cv::resize(right_band, r, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  cv::resize(mask_band, m, l.size(), 0, 0, cv::INTER_NEAREST);
  const int num = roundUpToDisparityStep((band.num_disparities + 1) / 2);
  if (l.cols <= num + config_.block_size || l.rows < config_.block_size) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const cv::Mat d16 = blockMatch(l, r, num);
  std::vector<float> found;
  for (int v = 0; v < m.rows; ++v) {
    const auto* mm = m.ptr<std::uint8_t>(v);
    const auto* d = d16.ptr<short>(v);
    for (int u = 0; u < m.cols; ++u) {
      if (!mm[u] || d[u] < 0) continue;
      const float disparity = 2.0f * d[u] / cv::StereoMatcher::DISP_SCALE + band.min_disparity;
      if (2 * u + band.left.x - disparity >= 0) found.push_back(disparity);  // not into the right band's padding
    }
  }
  if (static_cast<int>(found.size()) < kMinCoarseMatches) return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(found.begin(), found.begin() + found.size() / 2, found.end());
  const double median = found[found.size() / 2];
  const double far_end = farEndDisparity(calibration_, config_);
  // Beyond the far end only clearly (its median is good to a half-size pixel), inside the search (not piled up at
  // its ends, where a plain object's matches go) and where most of the object's pixels match and agree on it (a plain
  // object's few matches scatter, and their median with them); beyond the near end it is no object's. Neither is
  // trusted otherwise.
  if (median < far_end) {
    // A half-size pixel (2 px) clear of the far end and of the search's ends.
    if (median > far_end - 2 || median < band.min_disparity + 2 ||
        median > band.min_disparity + band.num_disparities - 2) {
      return std::numeric_limits<double>::quiet_NaN();
    }
    const auto near_median = std::count_if(found.begin(), found.end(), [median](float d) {
      return std::abs(d - median) <= kDisparitySlack;
    });
    return near_median > kMinFarEndAgreement * cv::countNonZero(m) ? median : std::numeric_limits<double>::quiet_NaN();
  }
  return inWorkspace(median) ? median : std::numeric_limits<double>::quiet_NaN();
}

void RoiStereoMatcher::checkMatchInputs(const RawFrame& left, const RawFrame& right, const cv::Rect& roi,
                                        const cv::Mat& mask, const cv::Mat& right_colour,
                                        const cv::Point& right_colour_origin, const cv::Mat& left_colour) const {
  const cv::Size size(calibration_.left.width, calibration_.left.height);
  if (left.size() != size || right.size() != size) {
    throw std::invalid_argument("RoiStereoMatcher::match: left and right must be frames of the calibrated size " +
                                std::to_string(size.width) + "x" + std::to_string(size.height));
  }
  if (roi.empty() || (roi & cv::Rect(cv::Point(), size)) != roi || mask.type() != CV_8UC1 || mask.size() != roi.size()) {
    throw std::invalid_argument("RoiStereoMatcher::match: roi must lie in the image and mask be CV_8UC1 of its size");
  }
  const cv::Rect right_colour_rect(right_colour_origin, right_colour.size());
  if (!right_colour.empty() && (right_colour.type() != CV_8UC1 || (right_colour_rect & cv::Rect(cv::Point(), size)) != right_colour_rect)) {
    throw std::invalid_argument("RoiStereoMatcher::match: the right colour mask must be CV_8UC1 and lie in the image");
  }
  if (!left_colour.empty() && (left_colour.type() != CV_8UC1 || left_colour.size() != leftColourRegion(roi).size())) {
    throw std::invalid_argument("RoiStereoMatcher::match: the left colour mask must be CV_8UC1 of leftColourRegion(roi)'s size");
  }
}

RoiStereoMatcher::DisparityWindow RoiStereoMatcher::disparityWindow(double silhouette_disparity, const cv::Rect& box) const {
  const auto [d_lo, d_hi] = workspaceDisparities();
  if (!std::isfinite(silhouette_disparity)) return {d_lo, roundUpToDisparityStep(d_hi - d_lo)};
  const double f = calibration_.focalPx();
  const double relief = silhouette_disparity * kVisibleDepthShare * std::max(box.width, box.height) / f;
  // (never more than block matching searches: a near, large object seen by a long baseline could ask for more)
  return {std::max(d_lo, static_cast<int>(std::floor(silhouette_disparity - kReliefBehind * relief)) - kDisparitySlack),
          std::min(kMaxSgbmDisparities,
                   roundUpToDisparityStep(static_cast<int>(std::ceil(kReliefSpan * relief)) + 2 * kDisparitySlack))};
}

RoiStereoMatcher::DisparityWindow RoiStereoMatcher::workspaceAndBeyond() const {
  const auto [d_lo, d_hi] = workspaceDisparities();
  // Only as far beyond as block matching's budget leaves: the workspace's near end is never given up for it.
  const int beyond = std::max({1, d_lo / kBeyondFarEndReach, d_hi + 1 - kMaxSgbmDisparities});
  return {beyond, std::min(kMaxSgbmDisparities, roundUpToDisparityStep(d_hi - beyond))};
}

RoiStereoMatcher::MatchBand RoiStereoMatcher::matchBand(const DisparityWindow& window, const cv::Rect& box) const {
  const cv::Size size(calibration_.left.width, calibration_.left.height);
  // Left band: the box plus margin, widened to the left by the window so every object pixel has its whole
  // search range (block matching leaves a band's first num_disparities columns unmatched). Right band: the
  // same rectangle moved left by the window's start, so block matching runs with disparities 0..num-1 (true
  // disparity = that + min_disparity). Near the image's left edge both may reach beyond it (padded): an object
  // there is still matched wherever the right camera sees it.
  // A pixel at column x is in the right image only at disparities up to x: the window ends at the box's right
  // edge (an object near the left edge needs fewer disparities, and its band less padding).
  MatchBand band;
  band.min_disparity = window.min;
  band.num_disparities = std::min(window.num, roundUpToDisparityStep(std::max(0, box.br().x - window.min)));
  const int x0 = box.x - config_.margin_px - band.num_disparities, y0 = std::max(0, box.y - config_.margin_px);
  const int x1 = std::min(size.width, box.br().x + config_.margin_px),
            y1 = std::min(size.height, box.br().y + config_.margin_px);
  band.left = cv::Rect(x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0));
  band.right = band.left - cv::Point(window.min, 0);
  return band;
}

cv::Mat RoiStereoMatcher::blockMatch(const cv::Mat& left_band, const cv::Mat& right_band, int num_disparities) const {
  SgbmParams sgbm;
  sgbm.num_disparities = num_disparities;
  sgbm.block_size = config_.block_size;
  sgbm.p1 = kP1PerBlockPixel * sgbm.block_size * sgbm.block_size;
  sgbm.p2 = kP2PerBlockPixel * sgbm.block_size * sgbm.block_size;
  sgbm.uniqueness_ratio = config_.uniqueness_ratio;
  sgbm.disp12_max_diff = kDisp12MaxDiff;
  return Sgbm3WayMatcher(sgbm).compute(left_band, right_band);
}

void RoiStereoMatcher::reproject(const RawFrame& left, const RawFrame& right, const cv::Mat& mask_band,
                                 const cv::Mat& disparity16, const MatchBand& band, const ViewAgreement& agreement,
                                 RoiPoints& out) const {
  const double f = calibration_.focalPx(), baseline = calibration_.baselineM(), nearest = nearestDepthM();
  // Sample on a grid coarse enough to keep at most ~max_points (DBSCAN and fitting cost grow with them).
  const int step = std::max(1, static_cast<int>(std::ceil(std::sqrt(out.mask_pixels / static_cast<double>(config_.max_points)))));
  const double cx = calibration_.left.P(0, 2), cy = calibration_.left.P(1, 2);
  // A point the two cameras see in other colours was matched onto something else: most often a nearer object that
  // hides this one from the right camera (docs/accuracy.md, "Points the two cameras see in other colours"). Not
  // checked where either frame is grey, or at a limit of 1 or more.
  const bool colour_frames = carriesColour(left.layout()) && carriesColour(right.layout());
  const bool check_colour = config_.max_colour_difference < 1 && colour_frames;
  const bool check_views = config_.max_unseen_share < 1 && !agreement.water.empty() && colour_frames;
  std::vector<Eigen::Vector3f> points;
  std::vector<cv::Point> left_at, right_at;  // each point's raw pixel in either frame, when checked
  for (int v = 0; v < mask_band.rows; ++v) {
    const auto* m = mask_band.ptr<std::uint8_t>(v);
    const auto* d = disparity16.ptr<short>(v);
    for (int u = 0; u < mask_band.cols; ++u) {
      if (!m[u] || d[u] < 0) continue;  // SGBM marks unmatched pixels with -16
      const double disparity = d[u] / static_cast<double>(cv::StereoMatcher::DISP_SCALE) + band.min_disparity;
      if (u + band.left.x - disparity < 0) continue;  // matched into the padding left of the right image
      const double z = f * baseline / disparity;
      if (z < nearest || z > config_.max_depth_m) continue;
      ++out.matched_pixels;
      if ((v % step) != 0 || (u % step) != 0) continue;
      const cv::Vec3d rect((u + band.left.x - cx) * z / f, (v + band.left.y - cy) * z / f, z);
      const cv::Vec3d raw = left_r_transposed_ * rect;
      points.emplace_back(static_cast<float>(raw[0]), static_cast<float>(raw[1]), static_cast<float>(raw[2]));
      if (!check_colour && !check_views) continue;
      const int row = v + band.left.y, right_column = static_cast<int>(std::lround(u + band.left.x - disparity));
      const cv::Vec2s l = left_map_xy_.at<cv::Vec2s>(row, u + band.left.x);
      const cv::Vec2s r = right_map_xy_.at<cv::Vec2s>(row, std::min(right_column, right_map_xy_.cols - 1));
      left_at.emplace_back(l[0], l[1]);
      right_at.emplace_back(r[0], r[1]);
    }
  }
  if (!check_colour && !check_views) {
    out.points = std::move(points);
    return;
  }
  const std::vector<cv::Vec3f> left_colour = coloursAround(left, left_at), right_colour = coloursAround(right, right_at);
  if (check_views) {
    countUnseenViews(left_at, right_at, wholeCells(left), wholeCells(right), left_colour, right_colour, agreement, out);
    out.unseen = out.compared_points >= kMinComparedPoints &&
                 out.unseen_points > config_.max_unseen_share * out.compared_points;
    if (out.unseen) return;
  }
  if (!check_colour) {
    out.points = std::move(points);
    return;
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (chromaDistance(left_colour[i], right_colour[i]) <= config_.max_colour_difference) {
      out.points.push_back(points[i]);
    } else {
      ++out.other_colour_points;
    }
  }
}

bool RoiStereoMatcher::inWorkspace(double disparity) const {
  const double fb = calibration_.focalPx() * calibration_.baselineM();
  return disparity >= farEndDisparity(calibration_, config_) && disparity <= fb / nearestDepthM();
}

StereoOrder RoiStereoMatcher::stereoOrder(const RawFrame& left, const RawFrame& right, const cv::Rect& roi) const {
  const auto [d_lo, d_hi] = workspaceDisparities();
  // Where the right camera's raw image shows the roi's centre at the workspace's far and near ends: the left raw
  // centre rectified, moved along the rectified row, turned back into the right camera's raw frame and distorted.
  const CameraCalibration &l = calibration_.left, &r = calibration_.right;
  const cv::Point2f centre(roi.x + roi.width / 2.0F, roi.y + roi.height / 2.0F);
  std::vector<cv::Point2f> rectified;
  cv::undistortPoints(std::vector<cv::Point2f>{centre}, rectified, cv::Mat(l.K), cv::Mat(l.D), cv::Mat(l.R));
  const double f = calibration_.focalPx();
  std::vector<cv::Point3f> rays;
  for (const int d : {d_lo, d_hi}) {
    const cv::Vec3d ray = r.R.t() * cv::Vec3d(rectified[0].x - d / f, rectified[0].y, 1.0);
    rays.emplace_back(ray[0], ray[1], ray[2]);
  }
  std::vector<cv::Point2f> raw;
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Mat(r.K), cv::Mat(r.D), raw);
  const bool projected = std::isfinite(raw[0].x) && std::isfinite(raw[1].x) && std::isfinite(raw[0].y) && std::isfinite(raw[1].y);
  if (!projected) return compareStereoOrder(left, right, roi, d_lo, d_hi, 0.0);
  const int far_shift = static_cast<int>(std::floor(centre.x - raw[0].x)), near_shift = static_cast<int>(std::ceil(centre.x - raw[1].x));
  return compareStereoOrder(left, right, roi, far_shift, near_shift, 0.5 * (raw[0].y + raw[1].y) - centre.y);
}

std::pair<int, int> RoiStereoMatcher::workspaceDisparities() const { return disparitiesOf(calibration_, config_); }

double RoiStereoMatcher::nearestDepthM() const { return nearestMatchedDepthM(calibration_, config_); }

cv::Rect RoiStereoMatcher::silhouetteBox(const cv::Rect& box) const {
  return cv::Rect(box.x - 2, box.y - 2, box.width + 4, box.height + 4) &
         cv::Rect(0, 0, calibration_.left.width, calibration_.left.height);
}

cv::Rect RoiStereoMatcher::silhouetteSpan(const cv::Rect& box) const {
  // The left silhouette lies in its rectified box; the right one somewhere in that box moved left by the
  // workspace's disparities.
  const auto [d_lo, d_hi] = workspaceDisparities();
  const cv::Rect left_rect = silhouetteBox(box);
  const int x0 = std::max(0, left_rect.x - d_hi);
  if (left_rect.empty() || left_rect.br().x - d_lo <= x0) return {};
  return cv::Rect(x0, left_rect.y, left_rect.br().x - x0, left_rect.height);
}

cv::Rect RoiStereoMatcher::leftColourRegion(const cv::Rect& roi) const {
  return cv::Rect(roi.x - kLeftColourMarginPx, roi.y, roi.width + 2 * kLeftColourMarginPx, roi.height) &
         cv::Rect(0, 0, calibration_.left.width, calibration_.left.height);
}

cv::Rect RoiStereoMatcher::rightColourRegion(const cv::Rect& roi) const {
  const cv::Rect span = silhouetteSpan(rectifiedBox(roi));
  return span.empty() ? cv::Rect() : sourceRegion(right_map_xy_(span), cv::Size(calibration_.right.width, calibration_.right.height));
}

double RoiStereoMatcher::silhouetteDisparity(const cv::Mat& mask, const cv::Rect& roi, const cv::Mat& right_colour,
                                             const cv::Point& right_colour_origin, const cv::Rect& box,
                                             const cv::Mat& around, const cv::Point& around_origin) const {
  const auto [d_lo, d_hi] = workspaceDisparities();
  const cv::Rect left_rect = silhouetteBox(box), span = silhouetteSpan(box);
  if (span.empty()) return std::numeric_limits<double>::quiet_NaN();
  const int span_x = span.x, span_width = span.width;
  // Column profiles over every `row_step`-th row of left_rect (the right one over columns [right_x0, right_x1)),
  // placed in the columns of `span`.
  cv::Mat right_band, rows;
  auto profiles = [&](int row_step, int right_x0, int right_x1, std::vector<double>& left, std::vector<double>& right) {
    const cv::Rect right_rect(right_x0, left_rect.y, right_x1 - right_x0, left_rect.height);
    // Bilinear remapping keeps the outline's sub-pixel position in the masks' soft edges.
    cv::Mat left_band;
    remapBand(mask, left_band, everyNthRow(left_map_xy_(left_rect), row_step), everyNthRow(left_map_fraction_(left_rect), row_step),
              roi.tl(), cv::INTER_LINEAR);
    remapBand(right_colour, right_band, everyNthRow(right_map_xy_(right_rect), row_step),
              everyNthRow(right_map_fraction_(right_rect), row_step), right_colour_origin, cv::INTER_LINEAR);
    cv::reduce(left_band, rows, 1, cv::REDUCE_MAX);
    const std::vector<double> l = columnProfile(left_band, rows), r = columnProfile(right_band, rows);
    left.assign(span_width, 0.0);
    right.assign(span_width, 0.0);
    std::copy(l.begin(), l.end(), left.begin() + (left_rect.x - span_x));
    std::copy(r.begin(), r.end(), right.begin() + (right_x0 - span_x));
  };
  // The right profile (all rows, over columns from right_x0) of what the left frame also sees at disparity `d`: an
  // object cut by the left frame's right edge runs on in the right frame, beyond the columns the left one shows.
  // Per row, the column that edge splits counts in part. Reads right_band and rows as the last profiles() left them
  // (the sub-pixel pass: every row).
  auto seenByBoth = [&](int right_x0, double d) {
    std::vector<double> right(span_width, 0.0);
    for (int v = 0; v < right_band.rows; ++v) {
      if (!rows.at<std::uint8_t>(v)) continue;
      const double end = left_frame_end_[left_rect.y + v] - d;  // the right column the left frame's edge falls on
      const auto* m = right_band.ptr<std::uint8_t>(v);
      for (int u = 0; u < right_band.cols; ++u) {
        const double weight = std::clamp(end - (right_x0 + u - 0.5), 0.0, 1.0);
        if (weight <= 0) break;
        right[right_x0 - span_x + u] += weight * m[u];
      }
    }
    return right;
  };
  // The whole-pixel shift from a quarter of the rows over the whole search range, then the sub-pixel one
  // from all rows over the matched window only.
  // (The right profile also over the columns a run-on past the right end is judged in; bestShift reads none of them.)
  std::vector<double> left, right;
  profiles(kCoarseRowStep, span_x,
           std::min(left_rect.br().x, left_rect.br().x - d_lo + kSilhouetteSlackPx + kRunOnPx + 1), left, right);
  const int shift = bestShift(left, right, d_lo, d_hi);
  if (shift < 0) return std::numeric_limits<double>::quiet_NaN();
  // The left frame's mask around the object (what touches it too), in the same columns and rows as the whole-pixel
  // pass's profiles, which are kept to judge a run-on at the sub-pixel disparity. An object the left frame's border
  // cuts is judged by no run-on: the right frame sees on beyond that border too (beyond the right one, and beyond the
  // top and bottom ones in rows that rectification pairs with the left frame's outside).
  // (Within kLeftColourMarginPx of a side the left frame's mask around it is cut short: as good as cut.)
  const bool cut = roi.y <= 0 || roi.br().y >= calibration_.left.height ||
                   leftColourRegion(roi).width < roi.width + 2 * kLeftColourMarginPx;
  const bool judge_run_on = !around.empty() && !cut;
  std::vector<double> left_around, whole_left, whole_right;
  if (judge_run_on) {
    // (In the columns of `span`, which end where left_rect does, and on beyond it.)
    const cv::Rect around_rect = cv::Rect(left_rect.x - kLeftColourMarginPx, left_rect.y,
                                          left_rect.width + 2 * kLeftColourMarginPx, left_rect.height) &
                                 cv::Rect(span_x, 0, left_map_xy_.cols - span_x, left_map_xy_.rows);
    cv::Mat around_band;
    remapBand(around, around_band, everyNthRow(left_map_xy_(around_rect), kCoarseRowStep),
              everyNthRow(left_map_fraction_(around_rect), kCoarseRowStep), around_origin, cv::INTER_LINEAR);
    const std::vector<double> a = columnProfile(around_band, rows);
    left_around.assign(around_rect.br().x - span_x, 0.0);
    std::copy(a.begin(), a.end(), left_around.begin() + (around_rect.x - span_x));
    whole_left = left;
    whole_right = right;
  }
  const int x0 = std::max(span_x, left_rect.x - shift - kSilhouetteSlackPx - 1);
  const int x1 = std::min(left_rect.br().x - d_lo, left_rect.br().x - shift + kSilhouetteSlackPx + 1);
  profiles(1, x0, x1, left, right);
  // The right profile compared only where the left frame sees the same at the disparity found, which moves where
  // that is: its fixed point (a pixel of disparity moves the edge by a column). One that does not settle, or lies
  // farther from the plain centroids' disparity than the slack columns are worth, means the centroids hold more
  // than the object (another one in the right mask): the plain disparity stands.
  const double plain = centroidShift(left, right, shift);
  if (judge_run_on && std::isfinite(plain) &&
      runsOnBeyondOutline(whole_left, left_around, whole_right, static_cast<int>(std::lround(plain)))) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  // (Far from that edge the right profile is whole at the plain disparity, and every step gives it again.)
  const double nearest_edge =
      *std::min_element(left_frame_end_.begin() + left_rect.y, left_frame_end_.begin() + left_rect.br().y);
  if (!std::isfinite(plain) || nearest_edge - plain >= x1 - 0.5) return plain;
  double disparity = plain;
  for (int i = 0; i < kMaxFrameEdgeSteps; ++i) {
    const double next = centroidShift(left, seenByBoth(x0, disparity), shift);
    if (!std::isfinite(next) || std::abs(next - plain) > kMaxFrameEdgeMovePx) return plain;
    const bool settled = std::abs(next - disparity) < kFrameEdgeTolerancePx;
    disparity = next;
    if (settled) return disparity;
  }
  return plain;
}

double nearestMatchedDepthM(const StereoCalibration& calibration, const StereoMatchConfig& workspace) {
  const double fb = calibration.focalPx() * calibration.baselineM();
  if (!(std::isfinite(fb) && fb > 0 && fb < 1e6)) {  // not a head's calibration: nothing to say beyond the config
    return workspace.min_depth_m;
  }
  return std::max(workspace.min_depth_m, fb / disparitiesOf(calibration, workspace).second);
}

}  // namespace underwater_stereo
