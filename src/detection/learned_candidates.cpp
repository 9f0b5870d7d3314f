// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/learned_candidates.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {
namespace {

/// Rejections are reported for proposals whose best colour got at least this share of the needed votes.
constexpr double kExplainShare = 0.5;

double overlap(const cv::Rect& a, const cv::Rect& b) {
  const double inter = (a & b).area();
  return inter / std::max(1, std::min(a.area(), b.area()));
}

std::string formatted(const char* format, double a, double b) {
  char text[96];
  std::snprintf(text, sizeof(text), format, a, b);
  return text;
}

}  // namespace

std::vector<std::string> LearnedColourConfig::validate() const {
  std::vector<std::string> p;
  if (!(min_confidence > 0 && min_confidence <= 1)) p.push_back("colour_model.min_confidence must be in (0, 1]");
  if (!(max_overlap >= 0 && max_overlap <= 1)) p.push_back("colour_model.max_overlap must be in [0, 1]");
  for (const auto& s : water.validate()) p.push_back("colour_model." + s);
  for (const auto& s : proposals.validate()) p.push_back("colour_model." + s);
  return p;
}

LearnedSearch findLearnedCandidates(const cv::Mat& bgr, const std::vector<ColourClass>& classes,
                                    const LearnedColourConfig& config, const CandidateConfig& candidates) {
  requireBgr8(bgr, "findLearnedCandidates");
  if (!config.model || config.model->empty()) throw std::invalid_argument("findLearnedCandidates: no colour model loaded");
  LearnedSearch out;
  out.contrast = measureWaterContrast(bgr, config.water);
  ProposalConfig proposals = config.proposals;
  proposals.min_area_px = candidates.min_area_px;
  proposals.max_area_px = candidates.max_area_px;
  // The model's colour k is the config's class designated[k] (-1: learnt but not designated here).
  std::vector<int> designated;
  for (const std::string& name : config.model->colours()) {
    const auto it = std::find_if(classes.begin(), classes.end(), [&](const ColourClass& c) { return c.name == name; });
    designated.push_back(it == classes.end() ? -1 : static_cast<int>(it - classes.begin()));
  }
  struct Named {
    BlobProposal proposal;
    ColourVerdict verdict;
  };
  std::vector<Named> named;
  for (BlobProposal& b : proposeBlobs(bgr, out.contrast, proposals)) {
    const ColourVerdict v = config.model->classify(b.features);
    if (v.colour < 0 || v.confidence < kExplainShare * config.min_confidence) continue;
    const std::string colour = config.model->colours()[v.colour];
    if (designated[v.colour] < 0) {
      out.rejected.push_back({b.roi, colour, v.confidence, "colour not designated in this configuration"});
    } else if (v.confidence < config.min_confidence) {
      out.rejected.push_back({b.roi, colour, v.confidence,
                              formatted("colour confidence %.2f under colour_model.min_confidence %.2f", v.confidence,
                                        config.min_confidence)});
    } else {
      named.push_back({std::move(b), v});
    }
  }
  std::stable_sort(named.begin(), named.end(),
                   [](const Named& a, const Named& b) { return a.verdict.confidence > b.verdict.confidence; });
  for (Named& n : named) {
    const bool same_object = std::any_of(out.candidates.begin(), out.candidates.end(), [&](const Candidate& kept) {
      return overlap(kept.roi, n.proposal.roi) > config.max_overlap;
    });
    if (same_object) continue;  // a weaker view of an object already taken: not a rejection
    if (out.candidates.size() >= static_cast<std::size_t>(candidates.max_candidates)) {
      out.rejected.push_back({n.proposal.roi, config.model->colours()[n.verdict.colour], n.verdict.confidence,
                              "more than candidates.max_candidates"});
      continue;
    }
    Candidate c;
    c.colour_index = designated[n.verdict.colour];
    c.roi = n.proposal.roi;
    c.mask = n.proposal.mask;
    c.area_px = n.proposal.area_px;
    c.colour_fraction = n.verdict.confidence;
    c.outline = classifyOutline(n.proposal.contour);
    c.mean_bgr = cv::mean(bgr(c.roi), c.mask);
    c.face_contrast = faceContrast(bgr(c.roi), c.mask);
    c.saliency_kind = n.proposal.kind;
    c.saliency_level = n.proposal.level;
    c.contour = std::move(n.proposal.contour);
    out.candidates.push_back(std::move(c));
  }
  return out;
}

}  // namespace underwater_stereo
