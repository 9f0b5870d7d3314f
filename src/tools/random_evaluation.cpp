// SPDX-License-Identifier: BSD-3-Clause
#include "random_evaluation.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <iomanip>
#include <map>
#include <optional>
#include <sstream>
#include <thread>

#include "tool_helpers.h"
#include "underwater_stereo/detection/image_quality.h"

namespace underwater_stereo {
namespace tools {
namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out + "\"";
}

std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s << std::setprecision(6) << v;
  return s.str();
}

/// A JSON list of `values`.
std::string numbers(const std::vector<float>& values) {
  std::string out = "[";
  for (std::size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + number(values[i]);
  return out + "]";
}

std::string vec(const Eigen::Vector3d& v) { return "[" + number(v.x()) + ", " + number(v.y()) + ", " + number(v.z()) + "]"; }
std::string rect(const cv::Rect& r) {
  return "[" + std::to_string(r.x) + ", " + std::to_string(r.y) + ", " + std::to_string(r.width) + ", " +
         std::to_string(r.height) + "]";
}

/// Counts and errors of one group of objects (and, for groups of whole pairs, frames and false detections).
struct Tally {
  int frames = 0, false_detections = 0, eligible = 0, found = 0, colour_right = 0, shape_eligible = 0, shape_right = 0;
  std::vector<double> range_err, position_err;

  void add(const ObjectRecord& o) {
    if (!o.eligible) return;
    ++eligible;
    if (!o.found) return;
    ++found;
    colour_right += o.detected_colour == o.colour;
    if (o.visible_pixels >= kMinShapePixels) {
      ++shape_eligible;
      shape_right += o.detected_shape == o.shape;
    }
    range_err.push_back(o.range_error);
    position_err.push_back(o.position_error);
  }
  void addPair(const PairRecord& p) {
    ++frames;
    false_detections += static_cast<int>(p.false_detections.size());
    for (const auto& o : p.objects) add(o);
  }
};

std::string percent(int n, int of) { return ratioCell(n, of, 100.0, 1); }

std::string percentile100(const std::vector<double>& v, double q) { return percentileCell(v, q, 100.0, 2); }

void printRow(std::ostream& out, const std::string& group, const std::string& bin, const Tally& t) {
  out << "| " << group << " | " << bin << " | " << (t.frames > 0 ? std::to_string(t.frames) : "-") << " | "
      << t.eligible << " | " << percent(t.found, t.eligible) << " | " << percent(t.colour_right, t.found) << " | "
      << percent(t.shape_right, t.shape_eligible) << " (" << t.shape_eligible << ") | "
      << percentile100(t.range_err, 0.5) << " | " << percentile100(t.range_err, 0.95) << " | "
      << percentile100(t.position_err, 0.95) << " | " << ratioCell(t.false_detections, t.frames, 1.0, 3) << " |\n";
}

/// Bins of a value by upper edges: "lo-hi" labels.
std::string binLabel(double value, const std::vector<double>& edges, int precision) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision);
  for (std::size_t i = 1; i < edges.size(); ++i) {
    if (value < edges[i] || i + 1 == edges.size()) {
      s << edges[i - 1] << "-" << edges[i];
      return s.str();
    }
  }
  return "?";
}

const std::vector<double> kRangeEdges{0.5, 1, 2, 3, 4, 5};
const std::vector<double> kTurbidityEdges{0, 0.25, 0.5, 0.75, 1};
const std::vector<double> kLumaEdges{0, 40, 80, 120, 160, 200, 255};
/// [px m] focal length x baseline: the disparity of an object 1 m away (the head's own optics: 218; the sampler's
/// limits, a 100 mm lens and a 2 m baseline, under 50 000).
const std::vector<double> kFocalBaselineEdges{0, 150, 250, 400, 600, 1000, 50000};

std::string waterName(double water_type) {
  return water_type < 0.5 ? "blue" : water_type < 1.5 ? "green" : "brown";
}

/// Objects grouped by `key`, in the order the keys sort.
void printObjectGroup(std::ostream& out, const std::string& group, const std::vector<PairRecord>& pairs,
                      const std::function<std::string(const ObjectRecord&)>& key) {
  std::map<std::string, Tally> bins;
  for (const auto& p : pairs) {
    for (const auto& o : p.objects) {
      if (o.eligible) bins[key(o)].add(o);
    }
  }
  for (const auto& [bin, t] : bins) printRow(out, group, bin, t);
}

/// Whole pairs grouped by `key` (their false detections count too).
void printPairGroup(std::ostream& out, const std::string& group, const std::vector<PairRecord>& pairs,
                    const std::function<std::string(const PairRecord&)>& key) {
  std::map<std::string, Tally> bins;
  for (const auto& p : pairs) bins[key(p)].addPair(p);
  for (const auto& [bin, t] : bins) printRow(out, group, bin, t);
}

/// Failure rank of an eligible object: higher is worse.
double severity(const ObjectRecord& o) {
  const double size = std::min(1.0, o.visible_pixels / 1e6);  // of two misses, the bigger object is worse
  if (!o.found) return 4.0 + size;
  if (o.detected_colour != o.colour) return 3.0 + size;
  if (o.visible_pixels >= kMinShapePixels && o.detected_shape != o.shape) return 2.0 + size;
  return std::min(1.0, o.range_error);
}

}  // namespace

const std::vector<std::string>& missCauseNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all{"frame spoiled"};
    for (int s = 0; s < kRejectionStageCount; ++s) all.push_back(rejectionStageName(static_cast<RejectionStage>(s)));
    all.push_back("no votes");
    return all;
  }();
  return names;
}

int objectUnder(const cv::Mat& labels, const std::vector<ObjectRecord>& objects, const cv::Rect& roi) {
  if (labels.type() != CV_16UC1) throw std::invalid_argument("objectUnder: truth labels must be CV_16UC1");
  const cv::Rect box = roi & cv::Rect(cv::Point(), labels.size());
  std::vector<int> counts(objects.size(), 0);
  for (int v = box.y; v < box.br().y; ++v) {
    const auto* row = labels.ptr<std::uint16_t>(v);
    for (int u = box.x; u < box.br().x; ++u) {
      if (row[u] > 0 && row[u] <= counts.size()) ++counts[row[u] - 1];
    }
  }
  int best_box = -1, most_pixels = -1;
  double best_iou = 0;
  for (std::size_t k = 0; k < counts.size(); ++k) {
    if (counts[k] == 0 || counts[k] < 0.2 * std::min<double>(box.area(), objects[k].visible_pixels)) continue;
    const double iou = boxIou(objects[k].roi, box);
    if (iou > best_iou) {
      best_iou = iou;
      best_box = static_cast<int>(k);
    }
    if (most_pixels < 0 || counts[k] > counts[most_pixels]) most_pixels = static_cast<int>(k);
  }
  return best_iou >= kSameBoxIou ? best_box : most_pixels;
}

PairRecord evaluatePair(const sim::SampledScene& sampled, const sim::RenderedPair& pair, const DetectionResult& result,
                        double luma) {
  PairRecord rec;
  rec.seed = sampled.seed;
  rec.turbidity = sampled.turbidity;
  rec.water_type = sampled.water_type;
  rec.target_luma = sampled.target_luma;
  rec.focal_px = sampled.scene.rig.focalPx();
  rec.baseline_m = sampled.scene.rig.baseline_m;
  rec.luma = luma;
  rec.quality = qualityStatusName(result.quality.status);
  rec.detect_ms = result.timings.total_ms;
  rec.looks_swapped = result.looks_swapped;
  const cv::Size size = pair.left_labels.size();
  const Eigen::Vector3d attenuation = sampled.scene.water.attenuation_per_m;
  for (std::size_t i = 0; i < pair.ground_truth.size(); ++i) {
    const sim::GroundTruthObject& gt = pair.ground_truth[i];
    ObjectRecord o;
    o.name = gt.name;
    o.colour = gt.colour;
    o.shape = shapeFromName(gt.shape, "ground truth of " + gt.name + ": shape");
    o.designated = i < sampled.designated.size() && sampled.designated[i];
    o.range_m = gt.range_m;
    o.visible_pixels = gt.visible_pixels;
    o.roi = gt.roi_left;
    o.cut_by_border = gt.visible_pixels > 0 && (o.roi.x == 0 || o.roi.y == 0 || o.roi.br().x == size.width ||
                                                o.roi.br().y == size.height);
    o.albedo = gt.albedo;
    o.size_m = gt.size_m;
    o.centre_m = gt.centre_left_m;
    o.transmission = (-attenuation * gt.range_m).array().exp().mean();
    o.eligible = o.designated && gt.visible_pixels >= kMinVisiblePixels && gt.range_m >= kMinRangeM &&
                 gt.range_m <= kMaxRangeM;
    rec.objects.push_back(o);
  }
  const auto lyingOn = [&](const cv::Rect& roi) { return objectUnder(pair.left_labels, rec.objects, roi); };
  for (const Detection& d : result.objects) {
    const int best = lyingOn(d.roi);
    if (best >= 0 && rec.objects[best].designated && !rec.objects[best].found) {
      // The first detection of a designated object; one of an object too small, near or far is no false one.
      ObjectRecord& o = rec.objects[best];
      o.found = true;
      o.detected_colour = d.colour;
      o.detected_shape = d.shape;
      o.detected_range_m = d.range_m;
      o.detected_centre_m = d.position_m;
      o.detected_roi = d.roi;
      o.range_error = std::abs(d.range_m - o.range_m) / o.range_m;
      o.position_error = (d.position_m - o.centre_m).norm() / o.range_m;
      o.detected_shape_features = d.shape_features;
      o.detected_check_features = d.check_features;
      continue;
    }
    rec.false_detections.push_back(
        {d.colour, d.shape, best >= 0 ? rec.objects[best].name : "", d.roi, d.range_m, d.check_features});
  }
  // A missed object's cause: the latest stage that turned down a region on it.
  std::vector<int> latest(rec.objects.size(), -1);
  std::vector<std::string> reason(rec.objects.size());  // the first rejection's of that stage
  for (const Rejection& r : result.rejected) {
    const int k = lyingOn(r.roi);
    if (k < 0 || static_cast<int>(r.stage) <= latest[k]) continue;
    latest[k] = static_cast<int>(r.stage);
    reason[k] = r.reason;
  }
  for (std::size_t k = 0; k < rec.objects.size(); ++k) {
    ObjectRecord& o = rec.objects[k];
    if (!o.eligible || o.found) continue;
    o.miss_cause = result.quality.spoiled() ? missCauseNames().front()
                   : latest[k] < 0        ? missCauseNames().back()
                                          : rejectionStageName(static_cast<RejectionStage>(latest[k]));
    if (!result.quality.spoiled() && latest[k] >= 0) o.miss_reason = reason[k];
  }
  return rec;
}

PairRuns runPairs(int pairs, int jobs, const std::function<PairRecord(int)>& run) {
  std::vector<std::optional<PairRecord>> done(static_cast<std::size_t>(std::max(0, pairs)));
  std::vector<std::string> errors(done.size());
  std::atomic<int> next{0};
  auto work = [&]() {
    for (int i = next++; i < pairs; i = next++) {
      try {
        done[static_cast<std::size_t>(i)] = run(i);
      } catch (const std::exception& e) {
        errors[static_cast<std::size_t>(i)] = e.what();
      }
    }
  };
  std::vector<std::thread> threads;
  for (int j = 1; j < jobs; ++j) threads.emplace_back(work);
  work();
  for (auto& t : threads) t.join();
  PairRuns out;
  for (std::size_t i = 0; i < done.size(); ++i) {
    if (done[i]) {
      out.records.push_back(std::move(*done[i]));
    } else {
      out.failures.emplace_back(static_cast<int>(i), errors[i]);
    }
  }
  return out;
}

void printSummary(std::ostream& out, const std::vector<PairRecord>& pairs) {
  out << "| group | bin | frames | objects | recall % | colour right % | shape right % (n >= " << kMinShapePixels
      << " px) | range err median % | range err p95 % | position err p95 % (of range) | false/frame |\n"
         "|---|---|---|---|---|---|---|---|---|---|---|\n";
  printPairGroup(out, "**all**", pairs, [](const PairRecord&) { return std::string("all"); });
  printObjectGroup(out, "range m", pairs, [](const ObjectRecord& o) { return binLabel(o.range_m, kRangeEdges, 1); });
  printPairGroup(out, "turbidity", pairs, [](const PairRecord& p) { return binLabel(p.turbidity, kTurbidityEdges, 2); });
  printPairGroup(out, "water", pairs, [](const PairRecord& p) { return waterName(p.water_type); });
  printPairGroup(out, "luma", pairs, [](const PairRecord& p) {
    std::string label = binLabel(p.luma, kLumaEdges, 0);
    return std::string(label.size() < 7 ? 7 - label.size() : 0, ' ') + label;  // sorts numerically
  });
  const bool optics_vary = std::any_of(pairs.begin(), pairs.end(), [&](const PairRecord& p) {
    return p.focal_px != pairs.front().focal_px || p.baseline_m != pairs.front().baseline_m;
  });
  if (optics_vary) {
    printPairGroup(out, "focal x baseline px m", pairs, [](const PairRecord& p) {
      std::string label = binLabel(p.focal_px * p.baseline_m, kFocalBaselineEdges, 0);
      return std::string(label.size() < 9 ? 9 - label.size() : 0, ' ') + label;  // sorts numerically
    });
  }
  printObjectGroup(out, "colour", pairs, [](const ObjectRecord& o) { return o.colour; });
  printObjectGroup(out, "shape", pairs, [](const ObjectRecord& o) { return shapeName(o.shape); });
  printObjectGroup(out, "cut by border", pairs, [](const ObjectRecord& o) { return o.cut_by_border ? "yes" : "no"; });
  out << "\nRecall: eligible objects with a detection on them (any colour); colour and shape right: of those found.\n";
  std::map<std::string, int> falses;
  for (const auto& p : pairs) {
    for (const auto& f : p.false_detections) {
      const auto on = std::find_if(p.objects.begin(), p.objects.end(), [&](const ObjectRecord& o) { return o.name == f.on; });
      falses[on == p.objects.end() ? "background" : on->designated ? "a second detection of one object"
                                                                    : "a " + on->colour + " distractor"]++;
    }
  }
  std::map<std::string, int> causes;
  for (const auto& p : pairs) {
    for (const auto& o : p.objects) {
      if (!o.miss_cause.empty()) causes[o.miss_cause]++;
    }
  }
  out << "Missed (the last stage that turned a region on it down):" << (causes.empty() ? " none" : "");
  for (const std::string& cause : missCauseNames()) {
    if (causes.count(cause)) out << " " << cause << " " << causes[cause] << ";";
  }
  out << "\n";
  out << "False detections on:" << (falses.empty() ? " none" : "");
  for (const auto& [what, n] : falses) out << " " << what << " " << n << ";";
  out << "\n";
  out << "Pairs taken for left and right swapped (nothing reported): "
      << std::count_if(pairs.begin(), pairs.end(), [](const PairRecord& p) { return p.looks_swapped; }) << " of "
      << pairs.size() << "\n";
}

void writeJson(std::ostream& out, const std::vector<PairRecord>& pairs, const std::string& config_path) {
  out << "{\"config\": " << quoted(config_path) << ",\n \"criteria\": {\"min_visible_pixels\": " << kMinVisiblePixels
      << ", \"min_shape_pixels\": " << kMinShapePixels << ", \"range_m\": [" << kMinRangeM << ", " << kMaxRangeM
      << "]},\n \"pairs\": [";
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const PairRecord& p = pairs[i];
    out << (i ? ",\n" : "\n") << "  {\"seed\": " << p.seed << ", \"turbidity\": " << number(p.turbidity)
        << ", \"water_type\": " << number(p.water_type) << ", \"water\": " << quoted(waterName(p.water_type))
        << ", \"target_luma\": " << number(p.target_luma) << ", \"luma\": " << number(p.luma)
        << ", \"focal_px\": " << number(p.focal_px) << ", \"baseline_m\": " << number(p.baseline_m)
        << ", \"quality\": " << quoted(p.quality) << ", \"render_ms\": " << number(p.render_ms)
        << ", \"detect_ms\": " << number(p.detect_ms) << ",\n   \"objects\": [";
    for (std::size_t k = 0; k < p.objects.size(); ++k) {
      const ObjectRecord& o = p.objects[k];
      out << (k ? ",\n    " : "\n    ") << "{\"name\": " << quoted(o.name) << ", \"colour\": " << quoted(o.colour)
          << ", \"shape\": " << quoted(shapeName(o.shape)) << ", \"designated\": " << (o.designated ? "true" : "false")
          << ", \"eligible\": " << (o.eligible ? "true" : "false") << ", \"range_m\": " << number(o.range_m)
          << ", \"visible_pixels\": " << o.visible_pixels << ", \"cut_by_border\": " << (o.cut_by_border ? "true" : "false")
          << ", \"roi\": " << rect(o.roi) << ", \"albedo\": " << vec(o.albedo) << ", \"size_m\": " << vec(o.size_m)
          << ", \"centre_m\": " << vec(o.centre_m) << ", \"transmission\": " << number(o.transmission)
          << ", \"found\": " << (o.found ? "true" : "false");
      if (!o.miss_cause.empty()) out << ", \"miss_cause\": " << quoted(o.miss_cause);
      if (!o.miss_reason.empty()) out << ", \"miss_reason\": " << quoted(o.miss_reason);
      if (o.found) {
        out << ", \"detected\": {\"colour\": " << quoted(o.detected_colour)
            << ", \"shape\": " << quoted(shapeName(o.detected_shape))
            << ", \"range_m\": " << number(o.detected_range_m) << ", \"centre_m\": " << vec(o.detected_centre_m)
            << ", \"roi\": " << rect(o.detected_roi) << ", \"range_error\": " << number(o.range_error)
            << ", \"position_error\": " << number(o.position_error)
            << ", \"shape_features\": " << numbers(o.detected_shape_features)
            << ", \"check_features\": " << numbers(o.detected_check_features) << "}";
      }
      out << "}";
    }
    out << "],\n   \"false_detections\": [";
    for (std::size_t k = 0; k < p.false_detections.size(); ++k) {
      const FalseRecord& f = p.false_detections[k];
      out << (k ? ", " : "") << "{\"colour\": " << quoted(f.colour) << ", \"shape\": " << quoted(shapeName(f.shape))
          << ", \"on\": " << quoted(f.on) << ", \"roi\": " << rect(f.roi) << ", \"range_m\": " << number(f.range_m)
          << ", \"check_features\": " << numbers(f.check_features) << "}";
    }
    out << "]}";
  }
  out << "\n ]}\n";
}

std::vector<std::pair<std::size_t, std::size_t>> worstFailures(const std::vector<PairRecord>& pairs, std::size_t k) {
  std::vector<std::pair<std::size_t, std::size_t>> all;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    for (std::size_t j = 0; j < pairs[i].objects.size(); ++j) {
      if (pairs[i].objects[j].eligible) all.emplace_back(i, j);
    }
  }
  std::stable_sort(all.begin(), all.end(), [&](const auto& a, const auto& b) {
    return severity(pairs[a.first].objects[a.second]) > severity(pairs[b.first].objects[b.second]);
  });
  // Only failures: an object found with the right colour and shape and within 3 % of range is none.
  all.erase(std::remove_if(all.begin(), all.end(),
                           [&](const auto& a) { return severity(pairs[a.first].objects[a.second]) < 0.03; }),
            all.end());
  if (all.size() > k) all.resize(k);
  return all;
}

cv::Mat failurePicture(const cv::Mat& left_bgr, const PairRecord& pair, const ObjectRecord& object,
                       const DetectionResult& result) {
  cv::Mat out = left_bgr.clone();
  const int thick = std::max(2, out.cols / 640);
  for (const Detection& d : result.objects) {
    cv::rectangle(out, d.roi, cv::Scalar(0, 0, 255), thick);
    cv::putText(out, d.colour + " " + shapeName(d.shape), d.roi.tl() + cv::Point(0, -6), cv::FONT_HERSHEY_SIMPLEX,
                0.4 * thick, cv::Scalar(0, 0, 255), thick);
  }
  cv::rectangle(out, object.roi, cv::Scalar(0, 255, 0), thick);
  std::ostringstream caption;
  caption << "seed " << pair.seed << ": " << object.name << " at " << std::fixed << std::setprecision(2) << object.range_m
          << " m, " << object.visible_pixels << " px: ";
  if (!object.found) caption << "MISSED";
  else caption << "seen as " << object.detected_colour << " " << object.detected_shape << " at " << object.detected_range_m << " m";
  caption << " | turbidity " << pair.turbidity << ", luma " << std::setprecision(0) << pair.luma;
  cv::putText(out, caption.str(), cv::Point(10, 12 * thick + 10), cv::FONT_HERSHEY_SIMPLEX, 0.45 * thick,
              cv::Scalar(255, 255, 255), thick);
  return out;
}

}  // namespace tools
}  // namespace underwater_stereo
