// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/colour_learning.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <tinyxml2.h>

#include "underwater_stereo/common/image_size.h"
#include "underwater_stereo/common/whole_file.h"
#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/detection/detector.h"

namespace underwater_stereo {
namespace {

/// Between this overlap with a labelled object (intersection over union) and kMatchIou a proposal is part of
/// an object or the object with its surroundings: neither example nor background.
constexpr double kIgnoreIou = 0.05;
/// Two labels of one frame whose boxes share this much of their union label one object twice (a box drawn again a
/// pixel or two off, perhaps with another colour): never two objects, one hidden exactly behind the other.
constexpr double kSameObjectIou = 0.9;
/// zoomedIn() enlarges a frame by a factor drawn from [kMinZoom, kMaxZoom].
constexpr double kMinZoom = 1.3, kMaxZoom = 2.0;

std::string trimmed(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t\r\n"), b = s.find_last_not_of(" \t\r\n");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

/// The index in `colours` of the colour a label names: all of it, or what follows its last '_' (buoy_red -> red);
/// -1 when it names none.
int colourNamedBy(const std::string& label, const std::vector<std::string>& colours) {
  const std::size_t underscore = label.find_last_of('_');
  const std::string suffix = underscore == std::string::npos ? label : label.substr(underscore + 1);
  for (std::size_t k = 0; k < colours.size(); ++k) {
    if (label == colours[k] || suffix == colours[k]) return static_cast<int>(k);
  }
  return -1;
}

std::string boxText(const cv::Rect& r) {
  return "[" + std::to_string(r.x) + ", " + std::to_string(r.y) + ", " + std::to_string(r.br().x) + ", " +
         std::to_string(r.br().y) + "]";
}

/// `text`, all of it, as a finite decimal number into `out`; false otherwise (stod would also read hexadecimal,
/// "0x20C" as 524, which no labelling tool writes).
bool decimalNumber(const std::string& text, double& out) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    return false;
  }
  if (used != text.size() || !std::isfinite(v) || text.find_first_not_of("0123456789+-.eE") != std::string::npos) {
    return false;
  }
  out = v;
  return true;
}

/// `parent`'s child element `key` (nullptr when it has none). @throw std::invalid_argument "`where` has two <key>"
/// when it has more than one: which of them the labeller meant is not for a reader to guess.
const tinyxml2::XMLElement* onlyChild(const tinyxml2::XMLElement& parent, const char* key, const std::string& where) {
  const tinyxml2::XMLElement* child = parent.FirstChildElement(key);
  if (child && child->NextSiblingElement(key)) throw std::invalid_argument(where + " has two <" + key + ">");
  return child;
}

/// The image size a VOC <annotation>'s <size> declares (empty when it has none, or a side of 0). @throw
/// std::invalid_argument naming `path` when its <width> or <height> is no whole number in [0, kMaxImageSidePx], or
/// when <size>, <width> or <height> is given twice (which one was meant is not known).
cv::Size declaredSize(const tinyxml2::XMLElement& annotation, const std::string& path) {
  const tinyxml2::XMLElement* size = onlyChild(annotation, "size", path);
  if (!size) return {};
  int side[2] = {0, 0};
  const char* keys[2] = {"width", "height"};
  for (int k = 0; k < 2; ++k) {
    const tinyxml2::XMLElement* field = onlyChild(*size, keys[k], path + ": <size>");
    if (!field) return {};  // a <size> holding only <depth>: no size declared
    const std::string value = trimmed(field->GetText() ? field->GetText() : "");
    double n = -1;
    if (!decimalNumber(value, n) || !(n >= 0 && n <= kMaxImageSidePx && n == std::floor(n))) {
      throw std::invalid_argument(path + ": <size> <" + keys[k] + "> '" + value + "' is not a whole number in [0, " +
                                  std::to_string(kMaxImageSidePx) + "]");
    }
    side[k] = static_cast<int>(n);
  }
  if (side[0] == 0 || side[1] == 0) return {};  // some tools write 0 x 0 for "not known"
  return {side[0], side[1]};
}

}  // namespace

bool centreInside(const cv::Rect& roi, const cv::Rect& box) {
  const cv::Point2d c(roi.x + roi.width / 2.0, roi.y + roi.height / 2.0);
  return c.x >= box.x && c.x <= box.br().x && c.y >= box.y && c.y <= box.br().y;
}

std::vector<LabelBox> readVocLabels(const std::string& path, cv::Size* declared_size) {
  // An XML library, not a text search: comments, attributes, a <part>'s own <bndbox> and unclosed elements are
  // XML's business (a search took a commented-out object, skipped <object id="0">, took a part's box).
  const std::string text = readWholeFile(path);
  const std::string not_voc = path + ": not a Pascal VOC annotation (no <annotation> element)";
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.data(), text.size()) != tinyxml2::XML_SUCCESS) {
    if (text.find("<annotation") == std::string::npos) throw std::invalid_argument(not_voc);
    throw std::invalid_argument(path + ": unreadable XML (" + std::string(doc.ErrorStr() ? doc.ErrorStr() : "") + ")");
  }
  const tinyxml2::XMLElement* annotation = doc.RootElement();
  if (!annotation || std::string(annotation->Name()) != "annotation") throw std::invalid_argument(not_voc);
  if (annotation->NextSiblingElement()) {  // files joined: the second's objects would be learnt as background
    throw std::invalid_argument(path + ": a second <" + std::string(annotation->NextSiblingElement()->Name()) +
                                "> after the <annotation> (two annotations joined in one file?)");
  }
  if (declared_size != nullptr) *declared_size = declaredSize(*annotation, path);
  std::vector<LabelBox> out;
  int index = 0;
  for (const tinyxml2::XMLElement* object = annotation->FirstChildElement("object"); object;
       object = object->NextSiblingElement("object"), ++index) {
    const std::string where = path + ": object " + std::to_string(index);
    const tinyxml2::XMLElement* name = onlyChild(*object, "name", where);
    LabelBox label;
    label.name = trimmed(name && name->GetText() ? name->GetText() : "");
    if (label.name.empty()) throw std::invalid_argument(where + " has no <name>");
    const std::string named = where + " (" + label.name + ")";
    const tinyxml2::XMLElement* box = onlyChild(*object, "bndbox", named);  // a <part>'s box is the part's
    if (!box) throw std::invalid_argument(named + " has no <bndbox>");
    double v[4];
    std::string written[4];  // as the file writes them, for messages
    const char* keys[4] = {"xmin", "ymin", "xmax", "ymax"};
    for (int k = 0; k < 4; ++k) {
      const tinyxml2::XMLElement* field = onlyChild(*box, keys[k], named);
      if (!field) throw std::invalid_argument(named + " has no <" + keys[k] + ">");
      const std::string& value = written[k] = trimmed(field->GetText() ? field->GetText() : "");
      if (!decimalNumber(value, v[k])) {
        throw std::invalid_argument(named + ": <" + keys[k] + "> '" + value + "' is not a number");
      }
      if (std::abs(v[k]) > kMaxImageSidePx) {  // beyond any image, and beyond an int once rounded
        throw std::invalid_argument(named + ": <" + keys[k] + "> " + value + " lies beyond any image (|value| > " +
                                    std::to_string(kMaxImageSidePx) + ")");
      }
    }
    if (!(v[2] > v[0] && v[3] > v[1])) {
      throw std::invalid_argument(named + ": empty box [" + written[0] + ", " + written[1] + ", " + written[2] + ", " +
                                  written[3] + "] (xmin, ymin, xmax, ymax: need xmax > xmin and ymax > ymin)");
    }
    const int x0 = static_cast<int>(std::floor(v[0])), y0 = static_cast<int>(std::floor(v[1]));
    label.box = cv::Rect(x0, y0, std::max(1, static_cast<int>(std::ceil(v[2])) - x0),
                         std::max(1, static_cast<int>(std::ceil(v[3])) - y0));
    for (std::size_t j = 0; j < out.size(); ++j) {
      // Twice the weight, or two colours for one object (perhaps drawn again a pixel off): a labelling slip.
      if (boxIou(out[j].box, label.box) >= kSameObjectIou) {
        const bool same = out[j].box == label.box;
        throw std::invalid_argument(named + ": box " + boxText(label.box) + " is " + (same ? "also" : "nearly") +
                                    " object " + std::to_string(j) + "'s (" + out[j].name +
                                    (same ? "" : ", " + boxText(out[j].box)) + "): one object labelled twice");
      }
    }
    out.push_back(label);
  }
  return out;
}

std::vector<std::string> LearningOptions::validate() const {
  std::vector<std::string> p = training.validate();
  if (colours.empty()) p.push_back("no colours to learn");
  for (std::size_t k = 0; k < colours.size(); ++k) {
    if (colours[k].empty()) p.push_back("colour " + std::to_string(k + 1) + " has no name");
    if (std::find(colours.begin(), colours.begin() + static_cast<std::ptrdiff_t>(k), colours[k]) !=
        colours.begin() + static_cast<std::ptrdiff_t>(k)) {
      p.push_back("colour '" + colours[k] + "' is named twice");
    }
  }
  if (min_label_px < 1) p.push_back("min_label_px must be >= 1");
  if (augment < 0 || augment > 20) p.push_back("augment must be in [0, 20]");
  if (zoom < 0 || zoom > 20) p.push_back("zoom must be in [0, 20]");
  for (const std::string& b : background_labels) {
    if (const int k = colourNamedBy(b, colours); k >= 0) {
      p.push_back("background label '" + b + "' names the colour " + colours[static_cast<std::size_t>(k)] +
                  " (by its name or the part after its last '_'): it would be learnt as that colour, not as background");
    }
  }
  return p;
}

int colourOfLabel(const std::string& name, const LearningOptions& options) {
  if (const int k = colourNamedBy(name, options.colours); k >= 0) return k;
  if (std::find(options.background_labels.begin(), options.background_labels.end(), name) != options.background_labels.end()) {
    return -1;
  }
  std::string known;
  for (const auto& c : options.colours) known += (known.empty() ? "" : ", ") + c;
  throw std::invalid_argument("label '" + name + "' names no designated colour (" + known +
                              "); learn it as background with --background " + name + ", or add its colour");
}

std::vector<std::string> labelProblems(const std::vector<LabelledFrame>& frames, const LearningOptions& options,
                                       bool coverage) {
  std::vector<std::string> problems = options.validate();
  std::vector<int> examples(options.colours.size(), 0);
  std::vector<std::vector<std::string>> too_short(options.colours.size());  // labels of a colour none can teach
  for (const LabelledFrame& f : frames) {
    if (f.image.empty() || f.image.type() != CV_8UC3) {
      problems.push_back(f.name + ": not an 8-bit colour image");
      continue;
    }
    const cv::Rect image(0, 0, f.image.cols, f.image.rows);
    if (!f.declared_size.empty() && f.declared_size != image.size()) {
      problems.push_back(f.name + ": its annotation declares a " + std::to_string(f.declared_size.width) + "x" +
                         std::to_string(f.declared_size.height) + " image, the image is " + std::to_string(image.width) +
                         "x" + std::to_string(image.height) + " (labels of another image, or of a resized copy)");
      continue;
    }
    for (std::size_t i = 0; i < f.labels.size(); ++i) {
      const LabelBox& l = f.labels[i];
      const std::string where = f.name + ": box " + std::to_string(i) + " (" + l.name + ") " + boxText(l.box);
      try {
        const int colour = colourOfLabel(l.name, options);
        // A label under min_label_px teaches nothing, unless zoomed copies (zoomedIn: up to kMaxZoom times nearer)
        // make it that tall.
        const bool teaches = l.box.height >= options.min_label_px ||
                             (options.zoom > 0 && kMaxZoom * l.box.height >= options.min_label_px);
        if (colour >= 0 && teaches) ++examples[colour];
        if (colour >= 0 && !teaches) too_short[colour].push_back(where);
      } catch (const std::invalid_argument& e) {
        problems.push_back(where + ": " + e.what());
      }
      if ((l.box & image).area() < l.box.area()) {
        problems.push_back(where + ": outside the " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                           " image");
      }
    }
  }
  for (std::size_t k = 0; coverage && k < options.colours.size(); ++k) {
    if (examples[k] == 0) {
      std::string shorter;  // labels under min_label_px teach nothing (learnt from neither as object nor background)
      for (std::size_t i = 0; i < too_short[k].size() && i < 3; ++i) shorter += (i ? "; " : "") + too_short[k][i];
      if (too_short[k].size() > 3) shorter += "; ...";
      problems.push_back("colour '" + options.colours[k] + "': no labelled example in " + std::to_string(frames.size()) +
                         " frames" +
                         (too_short[k].empty() ? ""
                                               : ": its labels are under --min-label-px (" +
                                                     std::to_string(options.min_label_px) +
                                                     " px tall), which teach nothing: " + shorter) +
                         " (label some, or leave it out with --colours)");
    }
  }
  return problems;
}

void checkLabels(const std::vector<LabelledFrame>& frames, const LearningOptions& options) {
  const std::vector<std::string> problems = labelProblems(frames, options);
  if (!problems.empty()) throw std::invalid_argument(joinProblems("bad labels", problems));
}

cv::Mat augmentedWater(const cv::Mat& bgr, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> veil(0.0, 0.35), gain(0.75, 1.3), exposure(0.7, 1.3), unit(0.0, 1.0);
  // A water colour between blue-green and green-brown (B, G, R in 0-255).
  const double t = unit(rng);
  const cv::Vec3d water = cv::Vec3d(150, 130, 40) * (1 - t) + cv::Vec3d(60, 130, 110) * t;
  const double a = veil(rng), e = exposure(rng);
  const cv::Vec3d g(gain(rng), gain(rng), gain(rng));
  cv::Mat out(bgr.size(), CV_8UC3);
  for (int y = 0; y < bgr.rows; ++y) {
    const auto* p = bgr.ptr<cv::Vec3b>(y);
    auto* o = out.ptr<cv::Vec3b>(y);
    for (int x = 0; x < bgr.cols; ++x) {
      for (int c = 0; c < 3; ++c) o[x][c] = cv::saturate_cast<std::uint8_t>(e * g[c] * ((1 - a) * p[x][c] + a * water[c]));
    }
  }
  return out;
}

LabelledFrame zoomedIn(const LabelledFrame& frame, unsigned seed, const LearningOptions& options) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> scale(kMinZoom, kMaxZoom), unit(0.0, 1.0);
  const double s = scale(rng);
  const cv::Size size = frame.image.size();
  cv::Mat larger;
  cv::resize(frame.image, larger, cv::Size(), s, s, cv::INTER_LINEAR);
  // The window: around a random labelled object of a colour (its centre somewhere inside), else anywhere.
  std::vector<cv::Point2d> centres;
  for (const LabelBox& l : frame.labels) {
    if (colourOfLabel(l.name, options) >= 0) centres.emplace_back(s * (l.box.x + l.box.width / 2.0), s * (l.box.y + l.box.height / 2.0));
  }
  const int max_x = larger.cols - size.width, max_y = larger.rows - size.height;
  cv::Point2d at(unit(rng) * max_x, unit(rng) * max_y);
  if (!centres.empty()) {
    const cv::Point2d c = centres[std::min(centres.size() - 1, static_cast<std::size_t>(unit(rng) * centres.size()))];
    at = cv::Point2d(c.x - (0.2 + 0.6 * unit(rng)) * size.width, c.y - (0.2 + 0.6 * unit(rng)) * size.height);
  }
  const cv::Point origin(std::clamp(static_cast<int>(at.x), 0, max_x), std::clamp(static_cast<int>(at.y), 0, max_y));
  LabelledFrame out;
  out.name = frame.name + " (zoomed)";
  out.image = larger(cv::Rect(origin, size)).clone();
  for (const LabelBox& l : frame.labels) {
    const cv::Rect scaled(static_cast<int>(std::floor(s * l.box.x)), static_cast<int>(std::floor(s * l.box.y)),
                          static_cast<int>(std::ceil(s * l.box.width)), static_cast<int>(std::ceil(s * l.box.height)));
    const cv::Rect inside = (scaled - origin) & cv::Rect(cv::Point(), size);
    if (inside.area() > 0) out.labels.push_back({l.name, inside});
  }
  return out;
}

namespace {

/// Rows of one image of a frame (its labels) added to `out`; counts coverage when `count` is set.
void addSamples(const cv::Mat& image, const LabelledFrame& frame, const Detector& proposer, const LearningOptions& options,
                bool count, FrameSamples& out) {
  const std::vector<BlobProposal> proposals = proposer.proposals(RawFrame(image));
  for (const LabelBox& l : frame.labels) {
    if (!count || colourOfLabel(l.name, options) < 0 || l.box.height < options.min_label_px) continue;
    ++out.objects;
    out.proposed += std::any_of(proposals.begin(), proposals.end(),
                                [&](const BlobProposal& b) { return boxIou(b.roi, l.box) >= kMatchIou; });
  }
  for (const BlobProposal& b : proposals) {
    int label = -1;
    bool ignore = false;
    for (const LabelBox& l : frame.labels) {
      const int colour = colourOfLabel(l.name, options);
      const double overlap = boxIou(b.roi, l.box);
      if (colour < 0 || overlap <= kIgnoreIou) continue;
      if (l.box.height < options.min_label_px || overlap < kMatchIou) {
        ignore = true;
      } else {
        label = colour;
      }
    }
    if (ignore && label < 0) continue;
    out.features.push_back(cv::Mat(1, static_cast<int>(b.features.size()), CV_32F, const_cast<float*>(b.features.data())));
    out.labels.push_back(label);
  }
}

}  // namespace

FrameSamples samplesOf(const LabelledFrame& frame, const Detector& proposer, const LearningOptions& options,
                       unsigned seed) {
  FrameSamples out;
  addSamples(frame.image, frame, proposer, options, true, out);
  for (int k = 0; k < options.augment; ++k) {
    addSamples(augmentedWater(frame.image, seed * 7919U + static_cast<unsigned>(k)), frame, proposer, options, false, out);
  }
  for (int k = 0; k < options.zoom; ++k) {
    const LabelledFrame nearer = zoomedIn(frame, seed * 7907U + static_cast<unsigned>(k), options);
    addSamples(nearer.image, nearer, proposer, options, false, out);
  }
  return out;
}

ColourModel learnColourModel(const std::vector<const FrameSamples*>& parts, const LearningOptions& options) {
  cv::Mat features;
  std::vector<int> labels;
  for (const FrameSamples* p : parts) {
    if (p->features.empty()) continue;
    features.push_back(p->features);
    labels.insert(labels.end(), p->labels.begin(), p->labels.end());
  }
  return ColourModel::train(features, labels, options.colours, options.training);
}

void LearningScore::add(const LearningScore& o) {
  if (labelled.empty()) {
    *this = o;
    return;
  }
  for (std::size_t k = 0; k < labelled.size(); ++k) {
    labelled[k] += o.labelled[k];
    found[k] += o.found[k];
    false_by_colour[k] += o.false_by_colour[k];
    for (std::size_t j = 0; j < confusion[k].size(); ++j) confusion[k][j] += o.confusion[k][j];
  }
  frames += o.frames;
  false_detections += o.false_detections;
}

double LearningScore::recall() const {
  int l = 0, f = 0;
  for (std::size_t k = 0; k < labelled.size(); ++k) {
    l += labelled[k];
    f += found[k];
  }
  return l > 0 ? double(f) / l : 0.0;
}

namespace {

/// Adds one frame's detections (those of at least their colour's `min_confidence`) to `s`.
void scoreFrame(const LabelledFrame& f, const std::vector<Detection>& objects, const std::vector<double>& min_confidence,
                const LearningOptions& options, LearningScore& s) {
  const std::size_t n = options.colours.size();
  ++s.frames;
  std::vector<bool> used(objects.size(), false), counted_object(objects.size(), false);
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const auto it = std::find(options.colours.begin(), options.colours.end(), objects[i].colour);
    const double needed = it == options.colours.end() ? 0.0 : min_confidence[it - options.colours.begin()];
    counted_object[i] = objects[i].confidence >= needed;
  }
  for (const LabelBox& l : f.labels) {
    const int colour = colourOfLabel(l.name, options);
    if (colour < 0) continue;
    int hit = -1, other = -1;
    for (std::size_t i = 0; i < objects.size(); ++i) {
      if (!counted_object[i] || used[i] || !centreInside(objects[i].roi, l.box)) continue;
      if (objects[i].colour == options.colours[colour]) {
        hit = static_cast<int>(i);
        break;
      }
      if (other < 0) other = static_cast<int>(i);
    }
    const bool counted = l.box.height >= options.min_label_px;
    if (hit >= 0) used[hit] = true;
    if (!counted) {
      if (other >= 0) used[other] = true;  // a far object found: neither target nor false
      continue;
    }
    ++s.labelled[colour];
    if (hit >= 0) {
      ++s.found[colour];
      ++s.confusion[colour][colour];
    } else if (other >= 0) {
      const auto it = std::find(options.colours.begin(), options.colours.end(), objects[other].colour);
      if (it != options.colours.end()) ++s.confusion[colour][it - options.colours.begin()];
    } else {
      ++s.confusion[colour][n];
    }
  }
  for (std::size_t i = 0; i < objects.size(); ++i) {
    if (!counted_object[i] || used[i]) continue;
    ++s.false_detections;
    const auto it = std::find(options.colours.begin(), options.colours.end(), objects[i].colour);
    if (it != options.colours.end()) ++s.false_by_colour[it - options.colours.begin()];
  }
}

LearningScore emptyScore(std::size_t colours) {
  LearningScore s;
  s.labelled.assign(colours, 0);
  s.found.assign(colours, 0);
  s.false_by_colour.assign(colours, 0);
  s.confusion.assign(colours, std::vector<int>(colours + 1, 0));
  return s;
}

}  // namespace

std::vector<std::vector<Detection>> detectionsOf(const Detector& detector, const std::vector<LabelledFrame>& frames) {
  std::vector<std::vector<Detection>> out;
  for (const LabelledFrame& f : frames) out.push_back(detector.detect2d(RawFrame(f.image)).objects);
  return out;
}

LearningScore scoreDetections(const std::vector<LabelledFrame>& frames,
                              const std::vector<std::vector<Detection>>& detections, const LearningOptions& options,
                              const std::vector<double>& min_confidence) {
  if (detections.size() != frames.size() || min_confidence.size() != options.colours.size()) {
    throw std::invalid_argument("scoreDetections: need one detection list per frame and one threshold per colour");
  }
  LearningScore s = emptyScore(options.colours.size());
  for (std::size_t i = 0; i < frames.size(); ++i) scoreFrame(frames[i], detections[i], min_confidence, options, s);
  return s;
}

std::vector<LearningScore> scoreAt(const Detector& detector, const std::vector<LabelledFrame>& frames,
                                   const LearningOptions& options, const std::vector<double>& min_confidences) {
  if (min_confidences.empty() || !std::is_sorted(min_confidences.begin(), min_confidences.end())) {
    throw std::invalid_argument("scoreAt: give thresholds in ascending order");
  }
  if (detector.config().candidates.source == ContourSource::kLearned &&
      min_confidences.front() > 0 && min_confidences.front() < detector.config().learned.min_confidence) {
    throw std::invalid_argument("scoreAt: threshold under the detector's colour_model.min_confidence");
  }
  const auto detections = detectionsOf(detector, frames);
  std::vector<LearningScore> out;
  for (double t : min_confidences) {
    out.push_back(scoreDetections(frames, detections, options, std::vector<double>(options.colours.size(), t)));
  }
  return out;
}

LearningScore score(const Detector& detector, const std::vector<LabelledFrame>& frames, const LearningOptions& options) {
  return scoreAt(detector, frames, options, {0.0}).front();
}

namespace {

/// Mean of the per-colour recalls (a colour without labels counts as found).
double balancedRecall(const LearningScore& s) {
  double sum = 0;
  for (std::size_t k = 0; k < s.labelled.size(); ++k) sum += s.labelled[k] ? double(s.found[k]) / s.labelled[k] : 1.0;
  return s.labelled.empty() ? 0.0 : sum / s.labelled.size();
}

}  // namespace

ThresholdChoice chooseThresholds(const std::vector<LabelledFrame>& frames,
                                 const std::vector<std::vector<Detection>>& detections, const LearningOptions& options,
                                 const std::vector<double>& grid, double max_false_per_frame) {
  const std::size_t n = options.colours.size();
  if (grid.empty() || n == 0 || std::pow(double(grid.size()), double(n)) > 1e5) {
    throw std::invalid_argument("chooseThresholds: need 1 to 1e5 threshold combinations (grid size ^ colours)");
  }
  ThresholdChoice best;
  bool best_within = false;
  std::vector<std::size_t> at(n, 0);
  for (bool more = true; more;) {
    std::vector<double> t(n);
    for (std::size_t k = 0; k < n; ++k) t[k] = grid[at[k]];
    const LearningScore s = scoreDetections(frames, detections, options, t);
    const bool within = s.false_detections <= max_false_per_frame * s.frames;
    // Within the false budget: the best balanced recall, then overall recall, then fewest false; outside it
    // (nothing fits yet): fewest false.
    bool better = best.min_confidence.empty() || (within && !best_within);
    if (!better && within == best_within) {
      const double b = balancedRecall(s), bb = balancedRecall(best.score);
      better = within ? (b > bb + 1e-12 || (b > bb - 1e-12 && (s.recall() > best.score.recall() + 1e-12 ||
                                                               (s.recall() > best.score.recall() - 1e-12 &&
                                                                s.false_detections < best.score.false_detections))))
                      : s.false_detections < best.score.false_detections;
    }
    if (better) {
      best.min_confidence = t;
      best.score = s;
      best_within = within;
    }
    more = false;
    for (std::size_t k = 0; k < n && !more; ++k) {
      if (++at[k] < grid.size()) more = true;
      else at[k] = 0;
    }
  }
  return best;
}

DetectorConfig proposerConfig(const DetectorConfig& base) {
  DetectorConfig c = base;
  c.candidates.source = ContourSource::kColourMask;
  c.learned.check_file.clear();
  c.learned.check.reset();
  return c;
}

DetectorConfig learnedConfig(const DetectorConfig& base, const std::string& model_file,
                             std::shared_ptr<const ColourModel> model, const LearningOptions& options) {
  DetectorConfig c = base;
  c.candidates.source = ContourSource::kLearned;
  c.learned.file = model_file;
  c.learned.model = std::move(model);
  c.learned.check_file.clear();
  c.learned.check.reset();
  c.colours.classes.clear();
  for (const std::string& name : options.colours) {
    ColourClass k;
    if (const ColourClass* in_base = findColourClass(base.colours.classes, name)) k = *in_base;
    k.name = name;
    k.min_confidence = 0;  // the base's own threshold belongs to the base's model
    c.colours.classes.push_back(k);
  }
  return c;
}

}  // namespace underwater_stereo
