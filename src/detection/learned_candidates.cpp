// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/learned_candidates.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <iterator>
#include <stdexcept>
#include <utility>

#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {
namespace {

/// Rejections are reported for proposals whose best colour got at least this share of the needed votes.
constexpr double kExplainShare = 0.5;

/// A view skipped as the same object as a candidate is its second view (LearnedSearch::second_views) only when their
/// boxes overlap less than this (intersection over union): a view of nearly the same box is the same measurement,
/// which the check would judge again at nearly the same score.
constexpr double kSecondViewMaxIou = 0.7;

/// Median of `values` (CV_32F) under `mask`.
double medianUnder(const cv::Mat& values, const cv::Mat& mask) {
  std::vector<float> v;
  for (int y = 0; y < values.rows; ++y) {
    for (int x = 0; x < values.cols; ++x) {
      if (mask.at<std::uint8_t>(y, x)) v.push_back(values.at<float>(y, x));
    }
  }
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

/// The object's own silhouette around a proposal: where the saliency exceeds half its median inside the
/// proposal (the edge of a blurred step lies halfway between object and water), the connected region that
/// overlaps the proposal most. A proposal cut at a fixed level is too tight on a contrasted object (only its
/// core) and too wide on a faint one (its halo); its size and its stereo silhouette need the edge. Kept as it
/// is when the re-cut leaks into the surroundings (grows more than kMaxGrowth times).
constexpr double kMaxGrowth = 3.0;
void cutAtItsEdge(const WaterContrast& contrast, BlobProposal& b) {
  const cv::Mat& saliency = contrast.saliency[static_cast<int>(b.kind)];
  const double level = 0.5 * medianUnder(saliency(b.roi), b.mask);
  if (!(level > 0)) return;
  const int grow = std::max(b.roi.width, b.roi.height) / 2 + 4;
  const cv::Rect window = (b.roi + cv::Size(2 * grow, 2 * grow) - cv::Point(grow, grow)) & cv::Rect(cv::Point(), saliency.size());
  WaterContrast part;
  part.saliency[static_cast<int>(b.kind)] = saliency(window);
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(salientMask(part, b.kind, level), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, window.tl());
  double best_overlap = 0;
  BlobProposal cut;
  for (auto& contour : contours) {
    const cv::Rect roi = cv::boundingRect(contour);
    const double overlap = (roi & b.roi).area();
    if (overlap <= best_overlap || contour.size() < 3) continue;
    best_overlap = overlap;
    cut.roi = roi;
    cut.contour = std::move(contour);
  }
  if (cut.contour.empty()) return;
  const double area = cv::contourArea(cut.contour);
  if (area > kMaxGrowth * b.area_px || area < b.area_px / kMaxGrowth) return;
  b.mask = filledOutline(cut.contour, cut.roi);
  b.roi = cut.roi;
  b.contour = std::move(cut.contour);
  b.area_px = area;
  b.level = level;
}

/// A problem of the water's or the proposals' settings named by its key in the configuration file
/// (colour_model.background_scale, not the core's water.background_scale).
std::string asYamlKey(const std::string& problem) {
  static const std::pair<const char*, const char*> kKeys[] = {{"water.background_scale", "background_scale"},
                                                              {"water.object_level", "water_object_level"},
                                                              {"proposals.levels", "levels"},
                                                              {"proposals.max_proposals", "max_proposals"},
                                                              {"proposals.piece_step", "piece_step"}};
  for (const auto& [core, yaml] : kKeys) {
    const std::string prefix = core;
    if (problem.compare(0, prefix.size(), prefix) == 0) return "colour_model." + std::string(yaml) + problem.substr(prefix.size());
  }
  return "colour_model." + problem;
}

std::string formatted(const char* format, double a, double b) {
  char text[96];
  std::snprintf(text, sizeof(text), format, a, b);
  return text;
}

/// `proposals` within the candidates' area limits.
ProposalConfig withCandidateAreas(ProposalConfig proposals, const CandidateConfig& candidates) {
  proposals.min_area_px = candidates.min_area_px;
  proposals.max_area_px = candidates.max_area_px;
  return proposals;
}

/// A region holds a piece when their boxes overlap this much of the smaller one (overlapOfSmaller: a region smaller
/// than the piece's box and inside it counts too) and their pixels more than half of the smaller mask's (sameRegion:
/// a region inside the box of the rest of a larger one, beside its pixels, holds no part of it).
constexpr double kPieceInside = 0.9, kPieceInsidePixels = 0.5;

/// Which regions stand for their objects, and the region each piece stands in place of. A region that holds
/// pieces (BlobProposal::piece, named with their own votes: `own_needed`) of two colours, or with kPiecesStand two
/// pieces of one colour that are not one region (sameRegion), may hold two objects: its pieces stand for it and it
/// does not. With kPiecesStand each such piece records the most confident region it stands in place of (`whole`, -1
/// for none; a region so recorded never stands, so findLearnedCandidates never moves from it), for the detector to
/// measure whole when its pieces prove one object in 3D (joinPieces; two pieces of one object that record different
/// regions are measured as their union). A piece cut from a region (its box inside the region's) and named with its
/// own votes a colour other than the region's (an object touching a distractor, the region named after their
/// mixture) stands besides the region, the more confident of the two taken (findLearnedCandidates); any other piece
/// does not (the region it was cut from names its object).
struct Standing {
  std::vector<bool> stands;
  std::vector<int> whole;
  /// With kPiecesStand: a piece standing in place of a region named its colour whose pieces are all named so too
  /// (and inside no region holding pieces of two colours): it stands there for stereo to tell two objects apart, and
  /// its colour is that region's (Candidate::colour_of_its_region).
  std::vector<bool> colour_of_region;
};
Standing standingFor(const std::vector<BlobProposal>& regions, const std::vector<ColourVerdict>& verdicts,
                     const std::vector<double>& own_needed, OneColourPieces one_colour) {
  std::vector<std::size_t> named_pieces;
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const ColourVerdict& v = verdicts[i];
    if (regions[i].piece && v.colour >= 0 && v.confidence >= own_needed[v.colour]) named_pieces.push_back(i);
  }
  Standing out{std::vector<bool>(regions.size(), false), std::vector<int>(regions.size(), -1),
               std::vector<bool>(regions.size(), false)};
  std::vector<bool> in_two_colours(regions.size(), false);
  for (std::size_t i = 0; i < regions.size(); ++i) {
    if (regions[i].piece) continue;
    std::vector<std::size_t> inside;
    for (std::size_t p : named_pieces) {
      const BlobProposal& piece = regions[p];
      if (overlapOfSmaller(piece.roi, regions[i].roi) >= kPieceInside &&
          sameRegion(piece.roi, piece.mask, regions[i].roi, regions[i].mask, kPieceInsidePixels)) {
        inside.push_back(p);
      }
    }
    const bool two_colours = std::any_of(inside.begin(), inside.end(), [&](std::size_t p) {
      return verdicts[p].colour != verdicts[inside.front()].colour;
    });
    bool two_objects = two_colours;
    for (std::size_t a = 0; a < inside.size() && !two_objects; ++a) {
      for (std::size_t b = a + 1; b < inside.size() && !two_objects; ++b) {
        const BlobProposal &pa = regions[inside[a]], &pb = regions[inside[b]];
        two_objects = one_colour == OneColourPieces::kPiecesStand &&
                      !sameRegion(pa.roi, pa.mask, pb.roi, pb.mask, kPieceInsidePixels);
      }
    }
    out.stands[i] = !two_objects;
    for (std::size_t p : inside) {
      const bool cut_from_it = (regions[p].roi & regions[i].roi).area() >= kPieceInside * regions[p].roi.area();
      if (two_objects || (cut_from_it && verdicts[p].colour != verdicts[i].colour)) out.stands[p] = true;
      if (two_colours) in_two_colours[p] = true;
      if (two_objects && !two_colours && verdicts[p].colour == verdicts[i].colour) out.colour_of_region[p] = true;
      int& whole = out.whole[p];
      if (two_objects && one_colour == OneColourPieces::kPiecesStand &&
          (whole < 0 || verdicts[i].confidence > verdicts[whole].confidence)) {
        whole = static_cast<int>(i);
      }
    }
  }
  for (std::size_t p = 0; p < regions.size(); ++p) {
    out.colour_of_region[p] = out.colour_of_region[p] && !in_two_colours[p];
  }
  return out;
}

}  // namespace

bool turnedDownByStereo(RejectionStage stage) {
  return stage >= RejectionStage::kNotSeenByRight && stage <= RejectionStage::kCheckAfterStereo;
}

std::string rejectionStageName(RejectionStage stage) {
  switch (stage) {
    case RejectionStage::kColourNotDesignated: return "colour not designated";
    case RejectionStage::kColourUncertain: return "colour uncertain";
    case RejectionStage::kTooManyCandidates: return "too many candidates";
    case RejectionStage::kNotSeenByRight: return "not seen by the right camera";
    case RejectionStage::kBeyondFarEnd: return "beyond the far end";
    case RejectionStage::kTooFewPoints: return "too few 3D points";
    case RejectionStage::kNoFit: return "no shape fit";
    case RejectionStage::kWrongSize: return "wrong size";
    case RejectionStage::kCheckAfterStereo: return "turned down after stereo";
    case RejectionStage::kLeftRightSwapped: return "left and right swapped";
    case RejectionStage::kPieceOfObject: return "piece of an object";
  }
  return "?";
}

double boxIou(const cv::Rect& a, const cv::Rect& b) {
  const double inter = (a & b).area();
  return inter / std::max(1.0, double(a.area()) + b.area() - inter);
}

double overlapOfSmaller(const cv::Rect& a, const cv::Rect& b) {
  const double inter = (a & b).area();
  return inter / std::max(1, std::min(a.area(), b.area()));
}

bool sameRegion(const cv::Rect& a, const cv::Mat& a_mask, const cv::Rect& b, const cv::Mat& b_mask,
                double max_overlap) {
  if (overlapOfSmaller(a, b) <= max_overlap) return false;
  const cv::Rect both = a & b;
  cv::Mat common;
  cv::bitwise_and(a_mask(both - a.tl()), b_mask(both - b.tl()), common);
  const int smaller = std::min(cv::countNonZero(a_mask), cv::countNonZero(b_mask));
  return smaller == 0 || cv::countNonZero(common) > max_overlap * smaller;
}

std::vector<std::string> LearnedColourConfig::validate() const {
  std::vector<std::string> p;
  // The shares' ranges are detectorTunables()' (a share under 0.01 is not one tree in a hundred).
  if (!(min_confidence >= 0.01 && min_confidence <= 1)) p.push_back("colour_model.min_confidence must be in [0.01, 1]");
  if (!(max_overlap >= 0 && max_overlap <= 1)) p.push_back("colour_model.max_overlap must be in [0, 1]");
  if (!(check_min_confidence >= 0.01 && check_min_confidence <= 1)) {
    p.push_back("colour_model.check_min_confidence must be in [0.01, 1]");
  }
  if (!(check_from_confidence >= 0.01 && check_from_confidence <= 1)) {
    p.push_back("colour_model.check_from_confidence must be in [0.01, 1]");
  }
  for (const auto& s : water.validate()) p.push_back(asYamlKey(s));
  for (const auto& s : proposals.validate()) p.push_back(asYamlKey(s));
  return p;
}

LearnedProposals proposeLearned(const cv::Mat& bgr, const LearnedColourConfig& config, const CandidateConfig& candidates,
                                int threads) {
  LearnedProposals out;
  out.contrast = measureWaterContrast(bgr, config.water, threads);
  out.regions = proposeBlobs(bgr, out.contrast, withCandidateAreas(config.proposals, candidates), threads);
  return out;
}

LearnedSearch findLearnedCandidates(const cv::Mat& bgr, const std::vector<ColourClass>& classes,
                                    const LearnedColourConfig& config, const CandidateConfig& candidates, int threads,
                                    bool for_check, OneColourPieces one_colour) {
  requireBgr8(bgr, "findLearnedCandidates");
  if (!config.model || config.model->empty()) throw std::invalid_argument("findLearnedCandidates: no colour model loaded");
  LearnedProposals proposed = proposeLearned(bgr, config, candidates, threads);
  LearnedSearch out;
  out.contrast = std::move(proposed.contrast);
  // The model's colour k is the config's class designated[k] (-1: learnt but not designated here).
  // Its votes needed: the class's own min_confidence, else the model's.
  // With a check, what goes on to it (`needed`) is check_from_confidence; `own_needed` names pieces either way.
  std::vector<int> designated;
  std::vector<double> needed, own_needed;
  for (const std::string& name : config.model->colours()) {
    const ColourClass* k = findColourClass(classes, name);
    designated.push_back(k == nullptr ? -1 : static_cast<int>(k - classes.data()));
    own_needed.push_back(k != nullptr && k->min_confidence > 0 ? k->min_confidence : config.min_confidence);
    needed.push_back(for_check ? config.check_from_confidence : own_needed.back());
  }
  struct Named {
    BlobProposal proposal;
    ColourVerdict verdict;
    int whole = -1;  ///< into proposed.regions: the region it stands in place of (Standing::whole)
    bool colour_of_region = false;  ///< Standing::colour_of_region
  };
  std::vector<Named> named;
  std::vector<ColourVerdict> verdicts = config.model->classify(featureRows(proposed.regions));
  // The regions named a colour, cut into pieces along the image's steps and named too: two touching objects (or, in
  // one colour, one object cut in two: standingFor).
  std::vector<BlobProposal> pieces;
  {
    std::vector<const BlobProposal*> to_cut;  // into proposed.regions, which the pieces join below
    for (std::size_t i = 0; i < proposed.regions.size(); ++i) {
      const ColourVerdict& v = verdicts[i];
      if (v.colour >= 0 && v.confidence >= kExplainShare * needed[v.colour]) to_cut.push_back(&proposed.regions[i]);
    }
    pieces = cutIntoPieces(bgr, out.contrast, to_cut, withCandidateAreas(config.proposals, candidates));
  }
  if (!pieces.empty()) {
    const std::vector<ColourVerdict> piece_verdicts = config.model->classify(featureRows(pieces));
    verdicts.insert(verdicts.end(), piece_verdicts.begin(), piece_verdicts.end());
    std::move(pieces.begin(), pieces.end(), std::back_inserter(proposed.regions));
  }
  const Standing standing = standingFor(proposed.regions, verdicts, own_needed, one_colour);
  for (std::size_t i = 0; i < proposed.regions.size(); ++i) {
    if (!standing.stands[i]) continue;
    BlobProposal& b = proposed.regions[i];
    const ColourVerdict& v = verdicts[i];
    if (v.colour < 0 || v.confidence < kExplainShare * needed[v.colour]) continue;
    const std::string colour = config.model->colours()[v.colour];
    if (designated[v.colour] < 0) {
      out.rejected.push_back({b.roi, colour, v.confidence, RejectionStage::kColourNotDesignated,
                              "colour not designated in this configuration"});
    } else if (v.confidence < needed[v.colour]) {
      out.rejected.push_back({b.roi, colour, v.confidence, RejectionStage::kColourUncertain,
                              formatted(for_check ? "colour confidence %.2f under colour_model.check_from_confidence %.2f"
                                                  : "colour confidence %.2f under its min_confidence %.2f",
                                        v.confidence, needed[v.colour])});
    } else {
      named.push_back({std::move(b), v, standing.whole[i], standing.colour_of_region[i]});
    }
  }
  std::stable_sort(named.begin(), named.end(),
                   [](const Named& a, const Named& b) { return a.verdict.confidence > b.verdict.confidence; });
  const auto candidateOf = [&](Named& n) {
    if (!n.proposal.piece) cutAtItsEdge(out.contrast, n.proposal);  // cut again at its saliency, a piece joins its neighbour
    Candidate c;
    c.colour_index = n.verdict.colour >= 0 ? designated[n.verdict.colour] : -1;
    c.roi = n.proposal.roi;
    c.mask = n.proposal.mask;
    c.area_px = n.proposal.area_px;
    c.colour_fraction = n.verdict.confidence;
    c.outline = classifyOutline(n.proposal.contour);
    c.mean_bgr = cv::mean(bgr(c.roi), c.mask);
    c.face_contrast = faceContrast(bgr(c.roi), c.mask);
    c.saliency_kind = n.proposal.kind;
    c.saliency_level = n.proposal.level;
    c.piece = n.proposal.piece;
    c.colour_of_its_region = n.colour_of_region;
    c.colour_features = std::move(n.proposal.features);
    c.colour_features.insert(c.colour_features.end(), n.verdict.shares.begin(), n.verdict.shares.end());
    c.contour = std::move(n.proposal.contour);
    return c;
  };
  std::vector<int> whole_regions;  // into proposed.regions: the region of each of out.wholes
  for (Named& n : named) {
    const auto same_object = std::find_if(out.candidates.begin(), out.candidates.end(), [&](const Candidate& kept) {
      return sameRegion(kept.roi, kept.mask, n.proposal.roi, n.proposal.mask, config.max_overlap);
    });
    if (same_object != out.candidates.end()) {  // a weaker view of an object already taken: not a rejection
      std::optional<Candidate>& second = out.second_views[same_object - out.candidates.begin()];
      if (!second && boxIou(same_object->roi, n.proposal.roi) < kSecondViewMaxIou) second = candidateOf(n);
      continue;
    }
    if (out.candidates.size() >= static_cast<std::size_t>(candidates.max_candidates)) {
      out.rejected.push_back({n.proposal.roi, config.model->colours()[n.verdict.colour], n.verdict.confidence,
                              RejectionStage::kTooManyCandidates, "more than candidates.max_candidates"});
      continue;
    }
    out.candidates.push_back(candidateOf(n));
    out.second_views.emplace_back();
    out.whole_of.push_back(-1);
    if (n.whole >= 0) {  // the region a piece stands in place of (it never stands: not moved from), described once
      const auto known = std::find(whole_regions.begin(), whole_regions.end(), n.whole);
      out.whole_of.back() = static_cast<int>(known - whole_regions.begin());
      if (known == whole_regions.end()) {
        Named region{proposed.regions[n.whole], verdicts[n.whole]};
        out.wholes.push_back(candidateOf(region));
        whole_regions.push_back(n.whole);
      }
    }
  }
  return out;
}

}  // namespace underwater_stereo
