// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/miss_causes.h"

#include <algorithm>
#include <stdexcept>

#include "underwater_stereo/detection/learned_candidates.h"

namespace underwater_stereo {

std::string missCauseName(MissCause cause) {
  switch (cause) {
    case MissCause::kNoProposal: return "no proposal covers it";
    case MissCause::kUnderThreshold: return "votes under the threshold";
    case MissCause::kWrongColour: return "named another colour";
    case MissCause::kOverlapped: return "taken by an overlapping region";
    case MissCause::kOffLabel: return "detected off the label";
  }
  return "unknown";
}

MissExplanation explainMiss(const cv::Rect& label, int colour, const std::vector<cv::Rect>& proposals,
                            const std::vector<ColourVerdict>& verdicts, const std::vector<KeptRegion>& detections,
                            const std::vector<double>& min_confidence, double max_overlap) {
  if (proposals.size() != verdicts.size()) throw std::invalid_argument("explainMiss: one verdict per proposal needed");
  if (colour < 0 || colour >= static_cast<int>(min_confidence.size())) {
    throw std::invalid_argument("explainMiss: colour " + std::to_string(colour) + " has no threshold");
  }
  MissExplanation out;
  bool covered = false, passed = false, other = false, overlapped = false;
  // A detection of another colour centred on the label: the object was reported, as that colour.
  for (const KeptRegion& d : detections) other |= d.colour != colour && centreInside(d.roi, label);
  for (std::size_t i = 0; i < proposals.size(); ++i) {
    if (boxIou(proposals[i], label) < kMatchIou) continue;
    covered = true;
    const ColourVerdict& v = verdicts[i];
    if (v.colour < 0 || v.colour >= static_cast<int>(min_confidence.size())) continue;
    const bool enough = v.confidence >= min_confidence[v.colour];
    if (v.colour != colour) {
      other |= enough;
      continue;
    }
    out.best_confidence = std::max(out.best_confidence, v.confidence);
    if (!enough) continue;
    passed = true;
    overlapped |= std::any_of(detections.begin(), detections.end(), [&](const KeptRegion& d) {
      return d.colour == colour && overlapOfSmaller(d.roi, proposals[i]) > max_overlap && !centreInside(d.roi, label);
    });
  }
  out.cause = !covered ? MissCause::kNoProposal
              : other  ? MissCause::kWrongColour
              : passed ? (overlapped ? MissCause::kOverlapped : MissCause::kOffLabel)
                       : MissCause::kUnderThreshold;
  return out;
}

std::vector<Miss> explainMisses(const Detector& detector, const std::vector<LabelledFrame>& frames,
                                const std::vector<std::vector<Detection>>& detections, const LearningOptions& options,
                                const std::vector<double>& min_confidence) {
  const auto& model = detector.config().learned.model;
  if (detector.config().candidates.source != ContourSource::kLearned || !model || model->empty()) {
    throw std::invalid_argument("explainMisses: the detector has no learned colour model");
  }
  if (detections.size() != frames.size() || min_confidence.size() != options.colours.size()) {
    throw std::invalid_argument("explainMisses: need one detection list per frame and one threshold per colour");
  }
  // The model's colours in options' order (its thresholds); a colour it does not know is never named.
  std::vector<double> needed;
  for (const std::string& name : model->colours()) {
    const auto it = std::find(options.colours.begin(), options.colours.end(), name);
    needed.push_back(it == options.colours.end() ? 2.0 : min_confidence[it - options.colours.begin()]);
  }
  std::vector<Miss> out;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const LabelledFrame& frame = frames[f];
    std::vector<BlobProposal> proposals;
    std::vector<ColourVerdict> verdicts;
    bool looked = false;
    std::vector<KeptRegion> kept;
    for (const Detection& d : detections[f]) {
      const auto it = std::find(model->colours().begin(), model->colours().end(), d.colour);
      const int k = static_cast<int>(it - model->colours().begin());
      if (it != model->colours().end() && d.confidence >= needed[k]) kept.push_back({d.roi, k});
    }
    for (const LabelBox& l : frame.labels) {
      const int colour = colourOfLabel(l.name, options);
      if (colour < 0 || l.box.height < options.min_label_px) continue;
      const bool found = std::any_of(detections[f].begin(), detections[f].end(), [&](const Detection& d) {
        return d.colour == options.colours[colour] && d.confidence >= min_confidence[colour] && centreInside(d.roi, l.box);
      });
      if (found) continue;
      if (!looked) {
        proposals = detector.proposals(RawFrame(frame.image));
        verdicts = model->classify(featureRows(proposals));
        looked = true;
      }
      // The model's colour index of this label's colour.
      const auto mc = std::find(model->colours().begin(), model->colours().end(), options.colours[colour]);
      Miss m{frame.name, l, colour, {}};
      if (mc == model->colours().end()) {
        m.why.cause = MissCause::kUnderThreshold;
      } else {
        std::vector<cv::Rect> rois;
        for (const BlobProposal& b : proposals) rois.push_back(b.roi);
        m.why = explainMiss(l.box, static_cast<int>(mc - model->colours().begin()), rois, verdicts, kept, needed,
                            detector.config().learned.max_overlap);
      }
      out.push_back(m);
    }
  }
  return out;
}

}  // namespace underwater_stereo
