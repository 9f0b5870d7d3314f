// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/detector.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iomanip>
#include <iterator>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/detection/detection_check.h"
#include "underwater_stereo/detection/image_checks.h"
#include "underwater_stereo/detection/object_pieces.h"
#include "underwater_stereo/detection/roi_stereo_matcher.h"
#include "underwater_stereo/detection/sgbm_3way_matcher.h"
#include "underwater_stereo/detection/shape_features.h"
#include "underwater_stereo/detection/silhouette_depth.h"
#include "underwater_stereo/detection/stopwatch.h"
#include "underwater_stereo/detection/work_on_threads.h"

namespace underwater_stereo {
namespace {

/// Unit viewing rays (left optical frame, distortion removed) of a raw-image contour.
std::vector<Eigen::Vector3d> contourRays(const std::vector<cv::Point>& contour, const CameraCalibration& c) {
  std::vector<cv::Point2f> pixels(contour.begin(), contour.end()), normalised;
  cv::undistortPoints(pixels, normalised, cv::Mat(c.K), cv::Mat(c.D));
  std::vector<Eigen::Vector3d> rays;
  rays.reserve(normalised.size());
  for (const auto& p : normalised) rays.push_back(Eigen::Vector3d(p.x, p.y, 1.0).normalized());
  return rays;
}

/// 2D stages shared by detect() and detect2d(): quality, colour masks, candidates.
struct FrontEnd {
  QualityReport quality;             ///< judged at search_scale
  double scale = 1.0;                ///< the frame was searched scaled by this (scaleForSearch)
  const DetectorConfig* search = nullptr;  ///< the settings scaled for it: the detector's, or *dark_search
  std::shared_ptr<const DetectorConfig> dark_search;  ///< a dark frame's (its scale follows the frame's width)
  cv::Mat searched;  ///< the image the colours were searched in (scaled, enhanced, white-balanced)
  cv::Scalar gains{1.0, 1.0, 1.0};  ///< the grey-world gains it was balanced with (1: grey_world off)
  int saturation_median = 0;         ///< its median HSV saturation (sets the adaptive saturation floors)
  WaterContrast contrast;            ///< learned source: the searched image's water, contrast, spread and saliency
  std::vector<Candidate> candidates;
  /// learned source: for each candidate, the view measured in its place when it is turned down after stereo
  /// (LearnedSearch::second_views; empty otherwise)
  std::vector<std::optional<Candidate>> second_views;
  /// learned source: the region each candidate stands in place of as its piece, into `wholes`, else -1
  /// (LearnedSearch::whole_of; empty otherwise)
  std::vector<int> whole_of;
  std::vector<Candidate> wholes;
  std::vector<Rejection> rejected;   ///< learned source: what the colour model did not report (raw pixels)
};

/// BGR8 of `region` of the frame scaled by `scale`; at 0.5 straight from the Bayer cells, no demosaicing.
cv::Mat scaledDown(const RawFrame& frame, const cv::Rect& region, double scale) {
  if (scale >= 1.0) return frame.bgr(region);
  if (scale == 0.5 && region.x % 2 == 0 && region.y % 2 == 0) return frame.halfSizeBgr(region);
  cv::Mat small;
  cv::resize(frame.bgr(region), small, cv::Size(), scale, scale, cv::INTER_AREA);
  return small;
}

cv::Rect scaledRect(const cv::Rect& r, double k) {
  return cv::Rect(static_cast<int>(std::lround(r.x * k)), static_cast<int>(std::lround(r.y * k)),
                  static_cast<int>(std::lround(r.width * k)), static_cast<int>(std::lround(r.height * k)));
}

/// A candidate found in the frame scaled by `scale`, in full-resolution pixels; its mask is interpolated
/// (soft edges, 0-255), so its outline keeps sub-pixel information for the silhouette.
Candidate toFullResolution(Candidate c, double scale, const cv::Size& full) {
  if (scale >= 1.0) return c;
  const double k = 1.0 / scale;
  for (cv::Point& p : c.contour) {
    p = cv::Point(static_cast<int>(std::lround((p.x + 0.5) * k - 0.5)), static_cast<int>(std::lround((p.y + 0.5) * k - 0.5)));
  }
  const cv::Rect roi = scaledRect(c.roi, k) & cv::Rect(cv::Point(), full);
  cv::Mat mask;
  cv::resize(c.mask, mask, roi.size(), 0, 0, cv::INTER_LINEAR);
  c.mask = mask;
  c.roi = roi;
  c.area_px *= k * k;
  return c;
}

/// The right frame's mask of all designated colours over `region` (full resolution, soft edges), searched
/// exactly as the left frame was (scale, contrast enhancement, the left's gains and saturation floors), so
/// the two silhouettes are cut alike.
cv::Mat rightColourMask(const RawFrame& right, const cv::Rect& region, const FrontEnd& left, const DetectorConfig& config) {
  cv::Mat small = scaledDown(right, region, left.scale);
  if (left.quality.enhanced) small = enhanceContrast(small, config.quality);
  if (config.colours.grey_world) small = applyGains(small, left.gains);
  const cv::Mat any = colourMasks(small, left.search->colours, left.saturation_median).any;
  if (left.scale >= 1.0) return any;
  cv::Mat full;
  cv::resize(any, full, region.size(), 0, 0, cv::INTER_LINEAR);
  return full;
}

/// The searched image blurred as the colour search blurs it (learned source).
cv::Mat blurredForSearch(const cv::Mat& small, const DetectorConfig& search) {
  if (search.colours.blur_px <= 1) return small;
  cv::Mat blurred;
  cv::GaussianBlur(small, blurred, cv::Size(search.colours.blur_px, search.colours.blur_px), 0);
  return blurred;
}

/// A searched-scale mask over `region` at full resolution (soft edges).
cv::Mat atFullResolution(const cv::Mat& mask, const cv::Rect& region, double search_scale) {
  if (search_scale >= 1.0) return mask;
  cv::Mat full;
  cv::resize(mask, full, region.size(), 0, 0, cv::INTER_LINEAR);
  return full;
}

/// The right frame's salient pixels over `region` (full resolution, soft edges), cut at the candidate's
/// saliency and level against the left frame's water and spread, as the left frame's are (leftSalientMask).
cv::Mat rightSalientMask(const RawFrame& right, const cv::Rect& region, const FrontEnd& left, const Candidate& c,
                         const DetectorConfig& config) {
  const double k = left.scale;
  const cv::Mat small = blurredForSearch(scaledDown(right, region, k), *left.search);
  const cv::Mat& left_water = left.contrast.water;
  const cv::Rect in_water = cv::Rect(static_cast<int>(std::lround(region.x * k)), static_cast<int>(std::lround(region.y * k)),
                                     small.cols, small.rows) & cv::Rect(cv::Point(), left_water.size());
  cv::Mat water;
  if (in_water.size() == small.size()) {
    water = left_water(in_water);
  } else {
    cv::resize(left_water(in_water), water, small.size(), 0, 0, cv::INTER_LINEAR);
  }
  const WaterContrast contrast = contrastAgainst(small, water, left.contrast.stats, config.learned.water);
  return atFullResolution(salientMask(contrast, c.saliency_kind, c.saliency_level), region, k);
}

/// The left frame's salient pixels over `around` (full resolution, soft edges; the candidate's roi and what lies
/// beside it), cut at the candidate's saliency and level from the saliency the search computed: pixel by pixel, as
/// the right frame's are (the candidate's own mask is one filled region). `region`: colourSearchRegion of `around`,
/// so the cut inside it is the whole frame's.
cv::Mat leftSalientMask(const FrontEnd& left, const Candidate& c, const cv::Rect& around, const cv::Rect& region) {
  const double search_scale = left.scale;
  const cv::Size searched = left.contrast.water.size();
  const cv::Rect band = cv::Rect(static_cast<int>(std::lround(region.x * search_scale)),
                                 static_cast<int>(std::lround(region.y * search_scale)),
                                 static_cast<int>(std::lround(region.width * search_scale)),
                                 static_cast<int>(std::lround(region.height * search_scale))) &
                        cv::Rect(cv::Point(), searched);
  const cv::Mat mask = salientMask(left.contrast, c.saliency_kind, c.saliency_level, band);
  return atFullResolution(mask, region, search_scale)(around - region.tl()).clone();
}

/// How a learned candidate stood out from the water in the left frame's search, for RoiStereoMatcher's view check
/// (none without a level: the colour-mask source's candidates).
ViewAgreement viewAgreementOf(const Candidate& c, const FrontEnd& left, const DetectorConfig& config) {
  ViewAgreement a;
  if (!(c.saliency_level > 0) || left.contrast.water.empty()) return a;
  a.water = left.contrast.water;
  a.water_scale = left.scale;
  a.stats = left.contrast.stats;
  a.kind = c.saliency_kind;
  a.ratio_offset = config.learned.water.ratio_offset;
  a.level = c.saliency_level;
  return a;
}

/// `region` grown by what the colour search's blur and morphology reach (so the mask inside it is the
/// whole frame's), on the searched image's grid (even pixels at half size, every fourth at quarter size: the
/// right frame's mask then lies on the left one's pixels), inside `frame`; `left`: how the frame was searched.
cv::Rect colourSearchRegion(const cv::Rect& region, const FrontEnd& left, const cv::Size& frame) {
  const ColourMaskConfig& c = left.search->colours;
  const int reach = static_cast<int>(std::ceil((c.blur_px + c.open_kernel_px + c.close_kernel_px + 2) / left.scale));
  const long cells = std::lround(1.0 / left.scale);
  const int grid = std::abs(1.0 / left.scale - cells) < 1e-9 ? static_cast<int>(std::max(2L, cells)) : 2;
  auto down = [grid](int x) { return x / grid * grid; };
  const int x0 = std::max(0, down(region.x - reach)), y0 = std::max(0, down(region.y - reach));
  const int x1 = std::min(frame.width, down(region.br().x + reach + grid - 1)),
            y1 = std::min(frame.height, down(region.br().y + reach + grid - 1));
  return x1 > x0 && y1 > y0 ? cv::Rect(x0, y0, x1 - x0, y1 - y0) : cv::Rect();
}

/// Adds one object's stage times (the right frame's colour mask, rectify, matching, reprojection, cluster, fit).
void addObjectStages(StageTimings& into, const StageTimings& t) {
  into.colour_ms += t.colour_ms;
  into.rectify_ms += t.rectify_ms;
  into.matching_ms += t.matching_ms;
  into.reprojection_ms += t.reprojection_ms;
  into.cluster_ms += t.cluster_ms;
  into.fit_ms += t.fit_ms;
}

/// Pieces of one object: a near object split by a highlight or a shading band into detections reported in one
/// colour (the colour model may have named a piece another colour that the check renamed) whose 3D clusters nearly
/// touch. They are measured again as the one region they make together. "Nearly": within
/// kPieceGapInEps cluster radii (eps_m), chosen on the validation seeds 60000-60029 (evaluate_detector --random
/// 30): false detections per pair 0.400 without joining, 0.367 at 1 and 2 eps, 0.300 at 4 and 8 eps, recall
/// 63.6 % throughout; the band cut out of a near object leaves a gap wider than one eps.
constexpr double kPieceGapInEps = 4.0;

/// Detections in neighbouring colours (their configured hue ranges touch: red and orange, yellow and green;
/// hueNeighbours) may be pieces of one object, as those of one colour may, when their boxes also overlap this much
/// of the smaller one (a box's lit top face read yellow and its sides orange). The share colour_model.max_overlap's
/// default takes for one region, not tuned. Classes without a hue range (anyHue) neighbour none; a group may hold
/// red and yellow pieces through an orange one touching both.
constexpr double kTwoColourPieceOverlap = 0.3;

/// The pieces of one object are measured as the region they stood in place of only when they cover this much of it
/// as it is measured (shareCovered; cut again at its edge, it may take in more than its pieces: the floor around
/// them); else as their union. Pieces cut from a region cover all of it but the steps between them; not tuned.
constexpr double kPiecesCoverTheirRegion = 0.75;

/// Pieces of one object measured again as the one region they make together: the region they stood in place of
/// (`whole_of` into `wholes`, FrontEnd::whole_of) when the group is exactly the candidates that stood in its place
/// (regionOfPieces) and covers most of it (kPiecesCoverTheirRegion), else their union (joinedCandidate). The region,
/// no piece, is placed at its silhouette's depth and keeps its own outline and face contrast; either way the joined
/// detection is named as the group's surest piece of its colour. It takes the first piece's place and the others are
/// reported as rejected, naming it; when the joined region cannot be measured the pieces stay as they were.
/// @return for each candidate, whether it was in a group of pieces of one object (joined, or not measurable whole)
template <typename MeasureOne>
std::vector<bool> joinPieces(const std::vector<Candidate>& candidates, const std::vector<int>& whole_of,
                             const std::vector<Candidate>& wholes, const std::vector<ColourClass>& classes,
                             std::vector<std::optional<Detection>>& found, std::vector<Rejection>& why,
                             std::vector<StageTimings>& times, MeasureOne&& measureOne, const cv::Size& frame,
                             double gap_m) {
  std::vector<bool> in_group(found.size(), false);
  std::vector<int> index, colours;  // colours: of the reported detections, as class indices
  std::vector<std::vector<Eigen::Vector3f>> clusters;
  for (int k = 0; k < static_cast<int>(found.size()); ++k) {
    if (!found[k]) continue;
    index.push_back(k);
    const ColourClass* reported = findColourClass(classes, found[k]->colour);
    colours.push_back(reported != nullptr ? static_cast<int>(reported - classes.data()) : candidates[k].colour_index);
    clusters.push_back(found[k]->points);
  }
  const auto may_join = [&](int i, int j) {
    if (colours[i] == colours[j]) return true;
    const ColourClass &a = classes[colours[i]], &b = classes[colours[j]];
    return overlapOfSmaller(found[index[i]]->roi, found[index[j]]->roi) >= kTwoColourPieceOverlap && !a.anyHue() &&
           !b.anyHue() && hueNeighbours(a, b);
  };
  for (const std::vector<int>& group : piecesOfOneObject(may_join, clusters, gap_m)) {
    // Pieces in two colours: the joined region is reported in the colour of the largest summed piece area.
    std::map<int, double> area_in;
    for (int g : group) area_in[colours[g]] += candidates[index[g]].area_px;
    const int colour = std::max_element(area_in.begin(), area_in.end(), [](const auto& a, const auto& b) {
                         return a.second < b.second;
                       })->first;
    std::vector<Candidate> in_colour;  // the pieces' regions, each in the colour the joined detection is reported in
    for (int g : group) {
      in_colour.push_back(candidates[index[g]]);
      Candidate& piece = in_colour.back();
      // A piece the check renamed or one of another colour: its colour_fraction is the colour model's confidence
      // in another colour, so the joined region takes its description (confidence, learned features) from a
      // piece the model named this colour when there is one.
      if (piece.colour_index != colour) piece.colour_fraction = 0;
      piece.colour_index = colour;
    }
    std::vector<const Candidate*> pieces;
    for (const Candidate& c : in_colour) pieces.push_back(&c);
    const int first = index[group.front()];
    for (int g : group) in_group[index[g]] = true;
    Candidate whole = joinedCandidate(pieces, frame);
    std::vector<int> members;  // the group as candidate indices
    for (int g : group) members.push_back(index[g]);
    const int region = whole_of.empty() ? -1 : regionOfPieces(members, whole_of);
    if (region >= 0 && shareCovered(whole, wholes[region]) >= kPiecesCoverTheirRegion) {
      // The region as it was cut, named as its surest piece of the group's colour.
      Candidate described = std::move(whole);
      whole = wholes[region];
      whole.colour_index = described.colour_index;
      whole.colour_fraction = described.colour_fraction;
      whole.colour_features = std::move(described.colour_features);
    }
    StageTimings t;
    Rejection rejected;
    std::optional<Detection> joined = measureOne(whole, t, rejected);
    addObjectStages(times[first], t);
    if (!joined) continue;
    // As sure as its surest piece of that colour (the check may score the whole lower than each piece).
    for (int g : group) {
      if (colours[g] == colour) joined->confidence = std::max(joined->confidence, found[index[g]]->confidence);
    }
    for (std::size_t g = 1; g < group.size(); ++g) {
      const int k = index[group[g]];
      why[k] = Rejection{found[k]->roi, found[k]->colour, found[k]->confidence, RejectionStage::kPieceOfObject,
                         "a piece of the object at " + std::to_string(joined->range_m) + " m reported whole"};
      found[k].reset();
    }
    found[first] = std::move(joined);
  }
  return in_group;
}

/// Pieces that stood in place of one region of their colour (Candidate::colour_of_its_region) and that stereo found
/// to be objects apart (in no group of pieces of one object, `grouped`): the nearest hides the others, so its outline
/// is all its own, and it is measured again as a region is (placed at its silhouette's depth, not at its points';
/// in its colour, which the check did not rename: Detector::detect's checkUseFor). Its points alone put a partly seen
/// sphere up to a third of its radius near or far (config/scenes/crossing.yaml: the near buoy 1.90-2.11 m for 2.0 while
/// the far one emerged from behind it).
/// Where that measurement fails, the piece's stays. Pieces of two colours keep their points' depth (session 28).
template <typename MeasureOne>
void measureFrontPieces(const std::vector<Candidate>& candidates, const std::vector<int>& whole_of,
                        const std::vector<bool>& grouped, std::vector<std::optional<Detection>>& found,
                        std::vector<StageTimings>& times, MeasureOne&& measureOne) {
  std::map<int, std::vector<int>> apart;  // region -> its pieces reported apart
  for (int k = 0; k < static_cast<int>(whole_of.size()); ++k) {
    if (found[k] && !grouped[k] && candidates[k].colour_of_its_region && whole_of[k] >= 0) {
      apart[whole_of[k]].push_back(k);
    }
  }
  for (const auto& [region, pieces] : apart) {
    if (pieces.size() < 2) continue;
    const int nearest = *std::min_element(pieces.begin(), pieces.end(),
                                          [&](int a, int b) { return found[a]->range_m < found[b]->range_m; });
    Candidate front = candidates[nearest];
    front.piece = false;
    StageTimings t;
    Rejection rejected;
    std::optional<Detection> whole = measureOne(front, t, rejected);
    addObjectStages(times[nearest], t);
    if (!whole) continue;
    whole->confidence = std::max(whole->confidence, found[nearest]->confidence);
    found[nearest] = std::move(whole);
  }
}

/// The colour the check names a detection the colour model named `named`: its best colour when that is designated in
/// `classes` and its share of the votes exceeds the check's share for `named` by more than `margin` (at 1 never); else
/// `named`.
std::string colourAfterCheck(const ColourVerdict& v, const ColourModel& check, const std::string& named,
                             const std::vector<ColourClass>& classes, double margin) {
  const std::vector<std::string>& colours = check.colours();
  if (v.colour < 0 || colours[v.colour] == named) return named;
  const auto own = std::find(colours.begin(), colours.end(), named);
  const double own_share = own == colours.end() ? 0.0 : v.shares[1 + (own - colours.begin())];  // background first
  const bool designated = findColourClass(classes, colours[v.colour]) != nullptr;
  return designated && v.share - own_share > margin ? colours[v.colour] : named;
}

/// `frame` scaled for the search; sets `out`'s quality, scale and settings (`search`: those scaled for
/// search_scale). The learned search takes a dark frame (quality.enhanced: usable and darker than
/// quality.enhance_below) at dark_search_width_px across, when that is coarser than search_scale and the searched
/// image keeps kMinSearchSidePx per side.
cv::Mat scaleForSearch(const RawFrame& frame, const DetectorConfig& config, const DetectorConfig& search, FrontEnd& out) {
  const cv::Rect whole(cv::Point(), frame.size());
  const cv::Mat small = scaledDown(frame, whole, config.search_scale);
  out.quality = assessQuality(small, config.quality);
  out.scale = config.search_scale;
  out.search = &search;
  const double dark = static_cast<double>(config.dark_search_width_px) / frame.size().width;
  if (config.candidates.source != ContourSource::kLearned || !out.quality.enhanced || dark >= config.search_scale ||
      std::min(frame.size().width, frame.size().height) * dark < kMinSearchSidePx) {
    return small;
  }
  out.scale = dark;
  out.dark_search = std::make_shared<const DetectorConfig>(scaledForSearch(config, dark));
  out.search = out.dark_search.get();
  return scaledDown(frame, whole, dark);
}

/// The learned search's settings for a frame of `quality`: without pieces (colour_model.piece_step) in a dark one
/// (quality.enhanced), where the steps are mostly the sensor's noise and the objects pieces found were ranged wrong
/// (docs/accuracy.md, "Touching objects cut along steps").
LearnedColourConfig learnedSearchFor(const DetectorConfig& config, const QualityReport& quality) {
  LearnedColourConfig learned = config.learned;
  if (quality.enhanced) learned.proposals.piece_step = 0;
  return learned;
}

/// Quality and candidates of `frame`; `search`: the settings scaled for search_scale; `for_check`: the learned
/// search passes what the check after stereo is to judge; `one_colour`: what stands for a region cut into pieces of
/// one colour (kPiecesStand where stereo measures them).
FrontEnd runFrontEnd(const RawFrame& frame, const DetectorConfig& config, const DetectorConfig& search, StageTimings& t,
                     Stopwatch& watch, bool for_check, OneColourPieces one_colour) {
  FrontEnd out;
  const cv::Mat small = scaleForSearch(frame, config, search, out);
  t.quality_ms = watch.lapMs();
  if (out.quality.spoiled()) return out;
  if (config.candidates.source == ContourSource::kLearned) {
    // Contrast with the water is measured as a ratio normalised by the frame's own spread: no contrast
    // enhancement or white balance before it.
    out.searched = blurredForSearch(small, *out.search);
    LearnedSearch found = findLearnedCandidates(out.searched, config.colours.classes, learnedSearchFor(config, out.quality),
                                                out.search->candidates, config.pair_threads, for_check, one_colour);
    t.colour_ms = watch.lapMs();
    out.contrast = std::move(found.contrast);
    for (Candidate& c : found.candidates) {
      out.candidates.push_back(toFullResolution(std::move(c), out.scale, frame.size()));
    }
    for (std::optional<Candidate>& c : found.second_views) {
      out.second_views.push_back(c ? std::optional<Candidate>(toFullResolution(std::move(*c), out.scale, frame.size()))
                                   : std::nullopt);
    }
    out.whole_of = std::move(found.whole_of);
    for (Candidate& c : found.wholes) out.wholes.push_back(toFullResolution(std::move(c), out.scale, frame.size()));
    for (Rejection& r : found.rejected) {
      r.roi = scaledRect(r.roi, 1.0 / out.scale);
      out.rejected.push_back(std::move(r));
    }
    t.contours_ms = watch.lapMs();
    return out;
  }
  out.searched = out.quality.enhanced ? enhanceContrast(small, config.quality) : small;
  if (config.colours.grey_world) {
    out.gains = greyWorldGains(out.searched);
    out.searched = applyGains(out.searched, out.gains);
  }
  const ColourMasks masks = colourMasks(out.searched, out.search->colours);
  out.saturation_median = masks.saturation_median;
  t.colour_ms = watch.lapMs();
  for (Candidate& c : findCandidates(out.searched, masks, config.colours.classes, out.search->candidates)) {
    out.candidates.push_back(toFullResolution(std::move(c), out.scale, frame.size()));
  }
  t.contours_ms = watch.lapMs();
  return out;
}

/// `left_roi`: BGR8 of the raw left image over c.roi.
Detection describe2d(const Candidate& c, const cv::Mat& left_roi, const cv::Size& frame, const DetectorConfig& config) {
  Detection d;
  d.colour = config.colours.classes[c.colour_index].name;
  d.outline = c.outline;
  d.roi = c.roi;
  d.contour = c.contour;
  d.cut_by_border = std::any_of(c.contour.begin(), c.contour.end(), [&](const cv::Point& p) { return onImageBorder(p, frame); });
  d.measured_bgr = cv::mean(left_roi, c.mask);
  d.confidence = c.colour_fraction;
  return d;
}

/// Whether `a` and `b` hold the same pixels in the same layout (row by row: two cameras' frames differ by their
/// noise in the first row, so the comparison ends there).
bool sameImage(const RawFrame& a, const RawFrame& b) {
  const cv::Mat &x = a.data(), &y = b.data();
  if (a.layout() != b.layout() || x.size() != y.size() || x.type() != y.type()) return false;
  const std::size_t row_bytes = x.cols * x.elemSize();
  for (int r = 0; r < x.rows; ++r) {
    if (std::memcmp(x.ptr(r), y.ptr(r), row_bytes) != 0) return false;
  }
  return true;
}

}  // namespace

Detector::Detector(const DetectorConfig& config, const StereoCalibration& calibration)
    : config_(config), search_config_(scaledForSearch(config, config.search_scale)) {
  const auto problems = config_.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid detector configuration", problems));
  matcher_ = std::make_unique<RoiStereoMatcher>(calibration, config_.stereo);
}

Detector::Detector(const DetectorConfig& config) : config_(config), search_config_(scaledForSearch(config, config.search_scale)) {
  const auto problems = config_.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid detector configuration", problems));
}

Detector::~Detector() = default;

std::string Detector::workspaceNote() const {
  if (!matcher_ || matcher_->nearestDepthM() <= config_.stereo.min_depth_m) return "";
  const StereoCalibration& c = matcher_->calibration();
  std::ostringstream note;
  note << std::fixed << std::setprecision(3) << "objects nearer than " << matcher_->nearestDepthM()
       << " m are not ranged (stereo.min_depth_m " << std::defaultfloat << config_.stereo.min_depth_m
       << "): with focal length x baseline " << std::fixed
       << std::setprecision(0) << c.focalPx() * c.baselineM() << " px m the workspace spans more disparities than block "
       << "matching searches (" << kMaxSgbmDisparities << ")";
  return note.str();
}

std::vector<BlobProposal> Detector::proposals(const RawFrame& frame) const {
  if (frame.empty()) throw std::invalid_argument("Detector::proposals: empty frame");
  FrontEnd scaled;
  const cv::Mat small = scaleForSearch(frame, config_, search_config_, scaled);
  if (scaled.quality.spoiled()) return {};
  const cv::Mat searched = blurredForSearch(small, *scaled.search);
  std::vector<BlobProposal> out =
      proposeLearned(searched, config_.learned, scaled.search->candidates, config_.pair_threads).regions;
  for (BlobProposal& b : out) b.roi = scaledRect(b.roi, 1.0 / scaled.scale);
  return out;
}

DetectionResult Detector::detect2d(const RawFrame& frame) const {
  if (frame.empty()) throw std::invalid_argument("Detector::detect2d: empty frame");
  requireImageSize(frame.size(), config_.search_scale, "Detector::detect2d");
  DetectionResult result;
  Stopwatch watch, total;
  const FrontEnd front =
      runFrontEnd(frame, config_, search_config_, result.timings, watch, false, OneColourPieces::kRegionStands);
  result.quality = front.quality;
  result.search_scale = front.scale;
  result.rejected = front.rejected;
  for (const Candidate& c : front.candidates) result.objects.push_back(describe2d(c, frame.bgr(c.roi), frame.size(), config_));
  result.timings.total_ms = total.lapMs();
  return result;
}

std::optional<Detection> Detector::measure(const Candidate& c, const RawFrame& left, const RawFrame& right,
                                           const cv::Mat& right_colour, const cv::Point& right_colour_origin,
                                           const cv::Mat& left_colour, const ViewAgreement& agreement,
                                           CheckUse check_use, StageTimings& t, Rejection& rejected,
                                           ObjectOrderEvidence* order) const {
  const ColourClass& colour = config_.colours.classes[c.colour_index];
  rejected = Rejection{c.roi, colour.name, c.colour_fraction, RejectionStage::kTooFewPoints, ""};
  const CameraCalibration& cal = matcher_->calibration().left;
  Stopwatch stage;
  const RoiPoints roi_points =
      matcher_->match(left, right, c.roi, c.mask, right_colour, right_colour_origin, left_colour, agreement);
  stage.lapMs();
  t.rectify_ms += roi_points.rectify_ms;
  t.matching_ms += roi_points.matching_ms;
  t.reprojection_ms += roi_points.reprojection_ms;
  if (order) {  // without a silhouette: is the object's view on the wrong side, as in a swapped pair?
    order->silhouette = std::isfinite(roi_points.silhouette_disparity);
    if (!order->silhouette) order->order = matcher_->stereoOrder(left, right, c.roi);
    t.matching_ms += stage.lapMs();
  }
  if (roi_points.beyond_far_end) {
    char text[200];
    std::snprintf(text, sizeof(text), "matched beyond the far end of the workspace (stereo.max_depth_m %.2f m): "
                  "farther than that", config_.stereo.max_depth_m);
    rejected.stage = RejectionStage::kBeyondFarEnd;
    rejected.reason = text;
    return std::nullopt;
  }
  if (roi_points.unseen) {
    rejected.stage = RejectionStage::kNotSeenByRight;
    rejected.reason = "not seen by the right camera where it matched: " + std::to_string(roi_points.unseen_points) +
                      " of " + std::to_string(roi_points.compared_points) +
                      " points do not stand out from the water there (a nearer object hides it from the right camera?)";
    return std::nullopt;
  }
  ClusterConfig cluster = config_.cluster;
  cluster.eps_m = neighbourhoodRadius(roi_points.points, cluster,
                                      matcher_->calibration().focalPx() * matcher_->calibration().baselineM());
  const std::vector<std::vector<int>> clusters = dbscan(roi_points.points, cluster);
  t.cluster_ms += stage.lapMs();
  if (clusters.empty() || static_cast<int>(clusters.front().size()) < config_.min_cluster_points) {
    rejected.reason = "too few 3D points (" + std::to_string(clusters.empty() ? 0 : clusters.front().size()) + " < " +
                      std::to_string(config_.min_cluster_points) + " in its main cluster, of " +
                      std::to_string(roi_points.points.size()) + " matched" +
                      (roi_points.other_colour_points > 0
                           ? "; " + std::to_string(roi_points.other_colour_points) +
                                 " more matched onto another colour in the right image: hidden from the right camera?)"
                           : ")");
    return std::nullopt;
  }
  const cv::Mat left_roi = left.bgr(c.roi);
  Detection d = describe2d(c, left_roi, left.size(), config_);
  for (int i : clusters.front()) d.points.push_back(roi_points.points[i]);
  ShapeFit fit = fitShape(d.points, contourRays(c.contour, cal), outlineCues(c, left_roi, left.size()), config_.shape);
  // A piece's outline is partly the edge of the object it touched: its silhouette's depth is not its own, and the
  // piece keeps its points' (docs/accuracy.md, "A piece keeps its points' depth"; the front one of pieces of one
  // colour that stereo tells apart is measured again as a region: measureFrontPieces).
  if (!c.piece) placeAtSilhouetteDepth(fit, roi_points.silhouette_disparity, matcher_->calibration(), d.cut_by_border);
  t.fit_ms += stage.lapMs();
  if (!fit.centre.allFinite() || !fit.size.allFinite()) {  // never report NaN
    rejected.stage = RejectionStage::kNoFit;
    rejected.reason = "shape fit gave no finite position or size";
    return std::nullopt;
  }
  const double extent = fit.size.maxCoeff();
  if ((colour.min_size_m > 0 && extent < colour.min_size_m) || (colour.max_size_m > 0 && extent > colour.max_size_m)) {
    rejected.stage = RejectionStage::kWrongSize;
    rejected.reason = "size " + std::to_string(extent) + " m outside [" + std::to_string(colour.min_size_m) + ", " +
                      std::to_string(colour.max_size_m) + "] m configured for " + colour.name;
    return std::nullopt;
  }
  d.shape = fit.shape;
  d.position_m = fit.centre;
  d.orientation = fit.orientation;
  d.size_m = fit.size;
  d.range_m = fit.centre.norm();
  d.fit_rmse_m = fit.rmse_m;
  d.shape_features = std::move(fit.features);
  const double matched = roi_points.mask_pixels > 0 ? roi_points.matched_pixels / double(roi_points.mask_pixels) : 0;
  if (!c.colour_features.empty()) {
    d.check_features = checkFeatures(c.colour_features, {d.range_m, fit.size.maxCoeff(), fit.size.minCoeff(),
                                                         static_cast<int>(d.shape), d.cut_by_border, d.fit_rmse_m, matched});
  }
  // How sure the colour search is: its confidence (the share of the votes, or its boosted trees' score), or with a
  // check after stereo the check's object score
  // (which weighs those votes with what stereo measured). The check names the colour where it is clearly surer of another one
  // (colour_model.check_rename_margin; docs/accuracy.md "The check names colours").
  double colour_share = c.colour_fraction;
  if (config_.learned.check) {
    const DetectionCheck& check = *config_.learned.check;
    colour_share = check.objectScore(d.check_features);
    if (check_use.may_rename) {
      d.colour = colourAfterCheck(check.colourVerdict(d.check_features), check.colours(), d.colour,
                                  config_.colours.classes, config_.learned.check_rename_margin);
    }
    if (check_use.may_reject && colour_share < config_.learned.check_min_confidence) {
      rejected.stage = RejectionStage::kCheckAfterStereo;
      rejected.confidence = colour_share;
      char text[128];
      std::snprintf(text, sizeof(text), "checked after stereo at %.2f m: an object at %.2f, under "
                    "colour_model.check_min_confidence %.2f", d.range_m, colour_share, config_.learned.check_min_confidence);
      rejected.reason = text;
      return std::nullopt;
    }
  }
  // Stereo noise grows with range: the fit residual is judged against 1 % of it.
  d.confidence = colour_share * std::min(1.0, matched / 0.5) * std::exp(-fit.rmse_m / (0.01 * std::max(d.range_m, 0.1)));
  return d;
}

DetectionResult Detector::detect(const RawFrame& left, const RawFrame& right) const {
  if (!matcher_) throw std::invalid_argument("Detector::detect: built without calibration (2D only)");
  if (left.empty() || right.empty()) throw std::invalid_argument("Detector::detect: empty frame");
  requireImageSize(left.size(), config_.search_scale, "Detector::detect");
  const CameraCalibration& cal = matcher_->calibration().left;
  if (left.size() != cv::Size(cal.width, cal.height) || right.size() != left.size()) {
    throw std::invalid_argument("Detector::detect: images are " + std::to_string(left.size().width) + "x" +
                                std::to_string(left.size().height) + " and " + std::to_string(right.size().width) + "x" +
                                std::to_string(right.size().height) + ", calibration is " + std::to_string(cal.width) +
                                "x" + std::to_string(cal.height));
  }
  DetectionResult result;
  Stopwatch watch, total;
  FrontEnd front =
      runFrontEnd(left, config_, search_config_, result.timings, watch, config_.learned.check != nullptr,
                  OneColourPieces::kPiecesStand);
  result.quality = front.quality;
  result.search_scale = front.scale;
  result.rejected = front.rejected;
  if (front.candidates.empty()) {
    result.timings.total_ms = total.lapMs();
    return result;
  }
  // One image as both views (a file given twice, a driver sending one buffer to both topics) would give every object
  // the disparity of the workspace's far end or a match of its texture with itself: a plausible, wrong range.
  if (sameImage(left, right)) {
    throw std::invalid_argument("Detector::detect: the left and right frames are the same image (one file given "
                                "twice, or one camera's buffer sent as both): no range can be measured");
  }
  // The right frame's colour mask (for the silhouettes) only where each object's silhouette can be, or the
  // whole frame when contrast enhancement (CLAHE: tiles over the whole frame) has to match the left's.
  const cv::Rect whole_frame(cv::Point(), right.size());
  const bool learned = config_.candidates.source == ContourSource::kLearned;
  const cv::Mat whole_right_colour = front.quality.enhanced && !learned
                                         ? rightColourMask(right, whole_frame, front, config_)
                                         : cv::Mat();
  result.timings.colour_ms += watch.lapMs();
  // Objects are independent: measured in parallel (stage times are summed over them), largest first so the
  // small ones fill in behind it on the other thread.
  const int n = static_cast<int>(front.candidates.size());
  // The check names colours, except in a dark frame and for a piece whose colour is its region's.
  const auto checkUseFor = [&](const Candidate& c) {
    CheckUse use;
    use.may_rename = !front.quality.enhanced && !c.colour_of_its_region;
    return use;
  };
  std::vector<int> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return front.candidates[a].roi.area() > front.candidates[b].roi.area(); });
  std::vector<std::optional<Detection>> found(n);
  std::vector<StageTimings> times(n);
  std::vector<Rejection> why(n);
  auto measureOne = [&](const Candidate& c, StageTimings& t, Rejection& rejected, ObjectOrderEvidence* pair_order,
                        CheckUse use) {
    cv::Mat right_colour = whole_right_colour;
    cv::Point origin;
    if (right_colour.empty()) {
      Stopwatch colour;
      const cv::Rect region = colourSearchRegion(matcher_->rightColourRegion(c.roi), front, right.size());
      if (!region.empty()) {
        right_colour = learned ? rightSalientMask(right, region, front, c, config_)
                               : rightColourMask(right, region, front, config_);
        origin = region.tl();
      }
      t.colour_ms = colour.lapMs();
    }
    cv::Mat left_colour;
    if (learned && !right_colour.empty()) {
      Stopwatch colour;
      const cv::Rect around = matcher_->leftColourRegion(c.roi);
      left_colour = leftSalientMask(front, c, around, colourSearchRegion(around, front, left.size()));
      t.colour_ms += colour.lapMs();
    }
    return measure(c, left, right, right_colour, origin, left_colour, viewAgreementOf(c, front, config_), use, t,
                   rejected, pair_order);
  };
  // On pair_threads threads of the detector's own (OpenCV may run single-threaded in a busy manager); one
  // object alone on this thread, where OpenCV's own parallel loops (block matching's stripes, remaps) may
  // spread it over the cores.
  std::vector<ObjectOrderEvidence> evidence(n);
  workOnThreads(n, config_.pair_threads, [&](int i) {
    const int k = order[i];
    found[k] = measureOne(front.candidates[k], times[k], why[k], &evidence[k], checkUseFor(front.candidates[k]));
  });
  // A candidate turned down after stereo gives way to the most confident view skipped as the same object (its own
  // piece where it was a region of it and what it touches), unless that view is another detection's object.
  std::vector<int> retried;
  for (int k = 0; k < static_cast<int>(front.second_views.size()); ++k) {
    if (found[k] || !turnedDownByStereo(why[k].stage) || !front.second_views[k]) continue;
    const Candidate& view = *front.second_views[k];
    const bool taken = std::any_of(order.begin(), order.end(), [&](int j) {
      return found[j] && sameRegion(front.candidates[j].roi, front.candidates[j].mask, view.roi, view.mask,
                                    config_.learned.max_overlap);
    });
    if (!taken) retried.push_back(k);
  }
  const int m = static_cast<int>(retried.size());
  std::vector<std::optional<Detection>> second(m);
  std::vector<StageTimings> second_times(m);
  std::vector<Rejection> second_why(m);
  evidence.resize(n + m);
  workOnThreads(m, config_.pair_threads, [&](int i) {
    second[i] = measureOne(*front.second_views[retried[i]], second_times[i], second_why[i], &evidence[n + i],
                           checkUseFor(*front.second_views[retried[i]]));
  });
  std::vector<Rejection> set_aside;  // views turned down that a second view replaced, and second views turned down
  for (int i = 0; i < m; ++i) {
    const int k = retried[i];
    addObjectStages(result.timings, second_times[i]);
    if (!second[i]) {
      set_aside.push_back(std::move(second_why[i]));
      continue;
    }
    set_aside.push_back(std::move(why[k]));
    found[k] = std::move(second[i]);
    front.candidates[k] = std::move(*front.second_views[retried[i]]);
    if (!front.whole_of.empty()) front.whole_of[k] = -1;
  }
  // One verdict per object on the pair's order, a second view being the object its candidate was: the candidate's
  // own, or its second view's where the candidate gave none (no silhouette, no plainly swapped view). Counted apart,
  // a swapped pair's candidates turned down by stereo and their second views finding a silhouette on a neighbour
  // outvoted the candidates that looked swapped.
  for (int i = 0; i < m; ++i) {
    ObjectOrderEvidence& own = evidence[retried[i]];
    if (!own.silhouette && !own.order.looksSwapped()) own = evidence[n + i];
  }
  evidence.resize(n);
  const PairOrder pair_order = pairOrder(evidence);
  result.looks_swapped = pair_order.looksSwapped();
  if (result.looks_swapped) {
    const std::string reason = "the pair looks swapped: " + std::to_string(pair_order.swapped) + " of " +
                               std::to_string(n) + " objects' views lie right of their left ones in the right image, " +
                               std::to_string(pair_order.silhouettes) +
                               " found their silhouette where it should be (left and right images the wrong way round?)";
    // Every view stereo measured or turned down was matched the wrong way round (its right views do not stand out
    // from the water where they matched, or show other colours: a swapped pair's objects are mostly turned down as
    // not seen by the right camera, or for too few points).
    const auto swapped = [&reason](Rejection& r) {
      if (!turnedDownByStereo(r.stage)) return;
      r.stage = RejectionStage::kLeftRightSwapped;
      r.reason = reason;
    };
    for (int k = 0; k < n; ++k) {
      if (found[k]) {
        why[k] = Rejection{found[k]->roi, found[k]->colour, found[k]->confidence, RejectionStage::kLeftRightSwapped,
                           reason};
        found[k].reset();
      } else {
        swapped(why[k]);
      }
    }
    for (Rejection& r : set_aside) swapped(r);
  } else {
    // Each piece passed the check and its colour is theirs: the check neither turns a region joined from them, nor
    // the front one measured again, down, nor renames it.
    const auto measureChecked = [&](const Candidate& c, StageTimings& t, Rejection& r) {
      CheckUse checked;
      checked.may_rename = false;
      checked.may_reject = false;
      return measureOne(c, t, r, nullptr, checked);
    };
    const std::vector<bool> grouped = joinPieces(front.candidates, front.whole_of, front.wholes,
                                                 config_.colours.classes, found, why, times, measureChecked, left.size(),
                                                 kPieceGapInEps * config_.cluster.eps_m);
    measureFrontPieces(front.candidates, front.whole_of, grouped, found, times, measureChecked);
  }
  std::move(set_aside.begin(), set_aside.end(), std::back_inserter(result.rejected));
  for (int k = 0; k < n; ++k) {
    addObjectStages(result.timings, times[k]);
    if (found[k]) {
      result.objects.push_back(std::move(*found[k]));
    } else {
      result.rejected.push_back(std::move(why[k]));
    }
  }
  result.timings.total_ms = total.lapMs();
  return result;
}

}  // namespace underwater_stereo
