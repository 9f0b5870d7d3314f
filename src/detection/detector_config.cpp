// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/detector_config.h"

#include <yaml-cpp/yaml.h>

#include <opencv2/core/utility.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "underwater_stereo/common/image_size.h"
#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/detection/detection_check.h"

namespace underwater_stereo {
namespace {

/// Reads one colour class; returns false when it has no hue range (only a learnt colour model needs none).
bool parseColour(YamlFields& f, const YAML::Node& node, const std::string& path, ColourClass& c) {
  f.onlyKeys(node, path, {"name", "hue", "saturation", "value", "min_contrast", "size_m", "min_confidence"});
  if (!node.IsMap()) return true;
  f.required(node, "name", path, c.name);
  std::vector<double> hue{double(c.hue_min), double(c.hue_max)}, sat{double(c.saturation_min), double(c.saturation_max)},
      val{double(c.value_min), double(c.value_max)};
  f.optionalVector(node, "hue", path, hue, 2);
  f.optionalVector(node, "saturation", path, sat, 2);
  f.optionalVector(node, "value", path, val, 2);
  f.optional(node, "min_contrast", path, c.min_contrast);
  f.optional(node, "min_confidence", path, c.min_confidence);
  std::vector<double> size{c.min_size_m, c.max_size_m};
  f.optionalVector(node, "size_m", path, size, 2);
  c.min_size_m = size[0];
  c.max_size_m = size[1];
  // HSV bounds are whole numbers: a NaN, a huge or a fractional one is named as written, never cast.
  auto bounds = [&](const std::vector<double>& v, const char* key, int& lo, int& hi) {
    for (double x : v) {
      if (!(std::abs(x) <= 1e6 && x == std::floor(x))) {
        f.fail(path + key + ": " + cv::format("%g", x) + " is not a whole number");
        return;
      }
    }
    lo = static_cast<int>(v[0]);
    hi = static_cast<int>(v[1]);
  };
  bounds(hue, "hue", c.hue_min, c.hue_max);
  bounds(sat, "saturation", c.saturation_min, c.saturation_max);
  bounds(val, "value", c.value_min, c.value_max);
  return static_cast<bool>(node["hue"]);
}

/// The YAML keys of `section` read by hand, besides its tunables.
const std::map<std::string, std::vector<std::string>> kOtherKeys = {
    {"candidates", {"source", "threshold", "dark_objects"}},
    {"colour_model", {"file", "check_file", "levels"}},
    {"shape", {"model_file"}}};

/// Reads the tunables of `section` (and, but at the top level, refuses keys that are neither one nor in
/// kOtherKeys).
void readTunables(YamlFields& f, const YAML::Node& node, const std::string& section, DetectorConfig& c) {
  std::vector<std::string> keys;
  if (const auto other = kOtherKeys.find(section); other != kOtherKeys.end()) keys = other->second;
  for (const DetectorTunable& t : detectorTunables()) {
    if (t.section == section) keys.emplace_back(t.key);
  }
  if (!section.empty()) f.onlyKeys(node, section + ".", keys);  // the top level's keys are checked by hand
  const std::string path = section.empty() ? "" : section + ".";
  for (const DetectorTunable& t : detectorTunables()) {
    if (t.section != section) continue;
    if (t.real) f.optional(node, t.key, path, *t.real(c));
    if (t.integer) f.optional(node, t.key, path, *t.integer(c));
  }
}

}  // namespace

// The field accessors: captureless lambdas (function pointers), one per row.
#define UWS_REAL(field) [](DetectorConfig& c) { return &c.field; }, nullptr
#define UWS_INT(field) nullptr, [](DetectorConfig& c) { return &c.field; }

const std::vector<DetectorTunable>& detectorTunables() {
  static const std::vector<DetectorTunable> table = {
      // section, key, min, max, dynamic_reconfigure name, doc, field
      {"quality", "too_dark_below", 0, 254, "too_dark_below", "Mean BT.601 luma under which a frame is spoiled",
       UWS_REAL(quality.too_dark_below)},
      {"quality", "too_bright_above", 1, 255, "too_bright_above", "Mean luma over which a frame is spoiled",
       UWS_REAL(quality.too_bright_above)},
      {"quality", "enhance_below", 0, 255, "enhance_below",
       "Usable frames darker than this are dark: CLAHE before an HSV search, the learned one coarser",
       UWS_REAL(quality.enhance_below)},
      {"quality", "dark_pixel_value", 0, 254, nullptr, "HSV V (0-255) under which a pixel counts as dark",
       UWS_INT(quality.dark_pixel_value)},
      {"quality", "bright_pixel_value", 1, 255, nullptr, "HSV V over which a pixel counts as bright (saturated)",
       UWS_INT(quality.bright_pixel_value)},
      {"quality", "clahe_clip_limit", 0.1, 100, nullptr, "CLAHE contrast limit", UWS_REAL(quality.clahe_clip_limit)},
      {"quality", "clahe_tiles", 1, 64, nullptr, "CLAHE grid is tiles x tiles", UWS_INT(quality.clahe_tiles)},
      {"candidates", "fixed_threshold", 0, 255, nullptr, "Grey level for threshold: fixed",
       UWS_INT(candidates.fixed_threshold)},
      {"candidates", "blur_kernel_px", 1, 51, nullptr, "Gaussian blur before grey thresholding [px, odd]",
       UWS_INT(candidates.blur_kernel_px)},
      {"candidates", "min_area_px", 1, 1.0e6, "min_area_px", "Smallest candidate contour [px]",
       UWS_REAL(candidates.min_area_px)},
      {"candidates", "max_area_px", 2, 1.0e9, nullptr, "Largest candidate contour [px]", UWS_REAL(candidates.max_area_px)},
      {"candidates", "min_colour_fraction", 0.01, 1, "min_colour_fraction",
       "Share of a contour's pixels in a designated colour", UWS_REAL(candidates.min_colour_fraction)},
      {"candidates", "max_candidates", 1, 1000, nullptr, "The largest this many candidates are kept",
       UWS_INT(candidates.max_candidates)},
      {"colour_model", "min_confidence", 0.01, 1, "min_confidence",
       "Share of the colour model's trees that must vote for a colour (colours without their own; with a check_file in 2D only)",
       UWS_REAL(learned.min_confidence)},
      {"colour_model", "check_from_confidence", 0.01, 1, "check_from_confidence",
       "With a check: share of the colour votes from which a region goes on to stereo and the check",
       UWS_REAL(learned.check_from_confidence)},
      {"colour_model", "check_min_confidence", 0.01, 1, "check_min_confidence",
       "How sure the check after stereo must be of an object (0-1; 0.5: its votes even)", UWS_REAL(learned.check_min_confidence)},
      {"colour_model", "check_rename_margin", 0, 1, nullptr,
       "With a check: its colour replaces the colour model's when its votes for it exceed those by this share (1: never)",
       UWS_REAL(learned.check_rename_margin)},
      {"colour_model", "max_overlap", 0, 1, nullptr,
       "Proposals overlapping a more confident one this much (box and pixels) are the same object",
       UWS_REAL(learned.max_overlap)},
      {"colour_model", "background_scale", 0.005, 0.5, nullptr,
       "The water colour: median over windows of about 5 / this pixels of the searched image",
       UWS_REAL(learned.water.background_scale)},
      {"colour_model", "water_object_level", 0, 1000, nullptr,
       "Regions standing out from a first water estimate at this level are left out of it (0: off)",
       UWS_REAL(learned.water.object_level)},
      {"colour_model", "max_proposals", 1, 10000, nullptr, "Proposals per frame, the most salient kept",
       UWS_INT(learned.proposals.max_proposals)},
      {"colour_model", "piece_step", 0, 10, nullptr,
       "Large regions also cut where ln(R/G) and ln(B/G) step over this per pixel, for touching objects (0: never)",
       UWS_REAL(learned.proposals.piece_step)},
      {"stereo", "min_depth_m", 0.1, 50, "min_depth_m", "Workspace: nearest depth searched [m]",
       UWS_REAL(stereo.min_depth_m)},
      {"stereo", "max_depth_m", 0.2, 100, "max_depth_m", "Workspace: farthest depth searched [m]",
       UWS_REAL(stereo.max_depth_m)},
      {"stereo", "block_size", 3, 11, nullptr, "SGBM block [px, odd]", UWS_INT(stereo.block_size)},
      {"stereo", "uniqueness_ratio", 0, 50, nullptr, "SGBM: the best cost beats the second by this [%]",
       UWS_INT(stereo.uniqueness_ratio)},
      {"stereo", "margin_px", 0, 200, nullptr, "Context around the ROI for matching [px]", UWS_INT(stereo.margin_px)},
      {"stereo", "erode_px", 0, 50, nullptr, "The object's mask shrunk by this before matching [px]",
       UWS_INT(stereo.erode_px)},
      {"stereo", "max_points", 10, 1000000, nullptr, "Mask pixels sampled to at most about this many points",
       UWS_INT(stereo.max_points)},
      {"stereo", "max_colour_difference", 0, 1, "max_colour_difference",
       "A point the two cameras see this far apart in chromaticity is dropped (a nearer object hides it; 1: never)",
       UWS_REAL(stereo.max_colour_difference)},
      {"stereo", "max_unseen_share", 0, 1, "max_unseen_share",
       "More of a candidate's points than this share not standing out from the water in the right frame where they "
       "matched: the right camera does not see it (a nearer object hides it), not ranged (1: never)",
       UWS_REAL(stereo.max_unseen_share)},
      {"cluster", "eps_m", 0.001, 1, "cluster_eps_m",
       "DBSCAN neighbourhood radius, the smallest (far objects: eps_disparity_px) [m]", UWS_REAL(cluster.eps_m)},
      {"cluster", "min_points", 1, 10000, "cluster_min_points", "DBSCAN core point neighbours",
       UWS_INT(cluster.min_points)},
      {"cluster", "eps_disparity_px", 0, 10, nullptr,
       "DBSCAN radius at least the depth this many pixels of disparity span at the points' median depth (0: eps_m)",
       UWS_REAL(cluster.eps_disparity_px)},
      {"shape", "min_points", 3, 1.0e6, nullptr, "Fewer points: shape unknown", UWS_REAL(shape.min_points)},
      {"shape", "plane_preference", 1, 10, nullptr, "Margin by which the model the outline does not favour must win",
       UWS_REAL(shape.plane_preference)},
      {"shape", "min_elongation", 1, 20, nullptr, "Outline length/width from which an object may be a cylinder",
       UWS_REAL(shape.min_elongation)},
      {"shape", "box_face_contrast", 0.01, 1000, nullptr, "Shading split into flat faces this clearly: a box",
       UWS_REAL(shape.box_face_contrast)},
      {"", "min_cluster_points", 3, 1.0e6, nullptr, "An object needs this many 3D points in its main cluster",
       UWS_INT(min_cluster_points)},
      {"", "search_scale", 0.1, 1, nullptr, "The 2D stages run on the frame scaled by this",
       UWS_REAL(search_scale)},
      {"", "dark_search_width_px", 0, kMaxImageSidePx, nullptr,
       "Learned source: frames darker than quality.enhance_below are searched at this width (0: off)",
       UWS_INT(dark_search_width_px)},
      {"", "pair_threads", 1, 16, nullptr, "Threads working on one pair (its 2D search, its objects)",
       UWS_INT(pair_threads)},
  };
  return table;
}

#undef UWS_REAL
#undef UWS_INT

std::string DetectorTunable::name() const { return *section ? std::string(section) + "." + key : std::string(key); }

double DetectorTunable::get(const DetectorConfig& c) const {
  auto& mutable_c = const_cast<DetectorConfig&>(c);  // the accessors serve reading and writing; nothing is written
  return real ? *real(mutable_c) : *integer(mutable_c);
}

void DetectorTunable::set(DetectorConfig& c, double value) const {
  if (real) *real(c) = value;
  else *integer(c) = static_cast<int>(std::lround(value));
}

std::vector<std::string> DetectorConfig::validate() const {
  std::vector<std::string> p;
  for (const auto& part : {quality.validate(), colours.validate(), candidates.validate(), stereo.validate(),
                           cluster.validate(), shape.validate()}) {
    p.insert(p.end(), part.begin(), part.end());
  }
  if (candidates.source == ContourSource::kLearned) {
    const auto l = learned.validate();
    p.insert(p.end(), l.begin(), l.end());
    if (!learned.model) {
      p.push_back("candidates.source is learned but no colour_model.file is loaded");
    } else {
      for (const ColourClass& c : colours.classes) {
        const auto& known = learned.model->colours();
        if (std::find(known.begin(), known.end(), c.name) == known.end()) {
          p.push_back("colours: '" + c.name + "' is designated but the colour model (" + learned.file +
                      ") has not learnt it; run learn_colours with examples of it");
        }
      }
    }
  } else if (learned.check) {
    p.push_back("colour_model.check_file: the check reads the learned colour search's votes; candidates.source is not "
                "learned");
  }
  for (const DetectorTunable& t : detectorTunables()) {
    const double v = t.get(*this);
    const auto named = [&t](const std::string& problem) {  // the section's own validate() said it already
      return problem.find(t.key) != std::string::npos && problem.find(t.section) != std::string::npos;
    };
    if (!(v >= t.min && v <= t.max) && std::none_of(p.begin(), p.end(), named)) {
      p.push_back(t.name() + " must be in [" + cv::format("%g", t.min) + ", " + cv::format("%g", t.max) + "], got " +
                  cv::format("%g", v));
    }
  }
  return p;
}

DetectorConfig parseDetectorConfig(const YAML::Node& root, const std::string& base_dir) {
  std::vector<std::string> problems;
  YamlFields f(problems);
  DetectorConfig c;
  f.onlyKeys(root, "", {"quality", "colours", "grey_world", "mask", "candidates", "colour_model", "stereo", "cluster",
                        "shape", "min_cluster_points", "search_scale", "dark_search_width_px", "pair_threads"});
  if (!root.IsMap()) throw std::invalid_argument(joinProblems("invalid detector configuration", problems));
  if (const YAML::Node q = root["quality"]) readTunables(f, q, "quality", c);
  std::vector<std::string> without_hue;
  if (const YAML::Node list = root["colours"]) {
    if (!list.IsSequence()) {
      f.fail("colours: expected a list of {name, hue, saturation, value}");
    } else {
      for (std::size_t i = 0; i < list.size(); ++i) {
        ColourClass cc;
        if (!parseColour(f, list[i], "colours[" + std::to_string(i) + "].", cc)) {
          without_hue.push_back("colours[" + std::to_string(i) + "].");
        }
        c.colours.classes.push_back(cc);
      }
    }
  }
  f.optional(root, "grey_world", "", c.colours.grey_world);
  if (const YAML::Node m = root["mask"]) {
    f.onlyKeys(m, "mask.", {"saturation_floor_factor", "saturation_floor_min", "blur_px", "open_kernel_px",
                            "close_kernel_px"});
    f.optional(m, "saturation_floor_factor", "mask.", c.colours.saturation_floor_factor);
    f.optional(m, "saturation_floor_min", "mask.", c.colours.saturation_floor_min);
    f.optional(m, "blur_px", "mask.", c.colours.blur_px);
    f.optional(m, "open_kernel_px", "mask.", c.colours.open_kernel_px);
    f.optional(m, "close_kernel_px", "mask.", c.colours.close_kernel_px);
  }
  if (const YAML::Node n = root["candidates"]) {
    readTunables(f, n, "candidates", c);
    std::string source = "colour_mask", threshold = "otsu";
    f.optional(n, "source", "candidates.", source);
    f.optional(n, "threshold", "candidates.", threshold);
    if (source == "colour_mask") c.candidates.source = ContourSource::kColourMask;
    else if (source == "grey_threshold") c.candidates.source = ContourSource::kGreyThreshold;
    else if (source == "learned") c.candidates.source = ContourSource::kLearned;
    else f.fail("candidates.source: '" + source + "' is not colour_mask, grey_threshold or learned");
    if (threshold == "otsu") c.candidates.threshold = ThresholdMode::kOtsu;
    else if (threshold == "fixed") c.candidates.threshold = ThresholdMode::kFixed;
    else f.fail("candidates.threshold: '" + threshold + "' is not otsu or fixed");
    f.optional(n, "dark_objects", "candidates.", c.candidates.dark_objects);
  }
  if (const YAML::Node m = root["colour_model"]; m && !m.IsMap()) {
    f.fail("colour_model: expected a map of {file, min_confidence, max_overlap, background_scale, water_object_level, levels, "
           "max_proposals, piece_step, check_file, check_min_confidence, check_from_confidence, check_rename_margin}");
  } else if (m) {
    LearnedColourConfig& l = c.learned;
    readTunables(f, m, "colour_model", c);
    f.optional(m, "file", "colour_model.", l.file);
    f.optional(m, "check_file", "colour_model.", l.check_file);
    if (const YAML::Node levels = m["levels"]) {
      l.proposals.levels.clear();
      for (std::size_t i = 0; levels.IsSequence() && i < levels.size(); ++i) {
        try {
          l.proposals.levels.push_back(levels[i].as<double>());
        } catch (const YAML::Exception&) {
          f.fail("colour_model.levels[" + std::to_string(i) + "]: expected a number");
        }
      }
      if (!levels.IsSequence()) f.fail("colour_model.levels: expected a list of saliency levels");
    }
    if (!l.file.empty()) {
      if (l.file.front() != '/' && !base_dir.empty()) l.file = base_dir + "/" + l.file;
      try {
        l.model = std::make_shared<const ColourModel>(ColourModel::load(l.file));
      } catch (const std::invalid_argument& e) {
        f.fail(std::string("colour_model.file: ") + e.what());
      }
    }
    if (!l.check_file.empty()) {
      if (l.check_file.front() != '/' && !base_dir.empty()) l.check_file = base_dir + "/" + l.check_file;
      if (!l.model) {
        f.fail("colour_model.check_file: the check reads the colour model's votes, and no colour_model.file is loaded");
      } else {
        try {  // a check learnt over another colour model's colours is refused by its feature names
          l.check = std::make_shared<const DetectionCheck>(DetectionCheck::load(l.check_file, l.model->colours()));
        } catch (const std::invalid_argument& e) {
          f.fail(std::string("colour_model.check_file: ") + e.what());
        }
      }
    }
  }
  for (const char* section : {"stereo", "cluster", "shape"}) {
    if (const YAML::Node node = root[section]) readTunables(f, node, section, c);
  }
  if (const YAML::Node s = root["shape"]; s && s.IsMap()) {
    f.optional(s, "model_file", "shape.", c.shape.model_file);
    if (!c.shape.model_file.empty()) {
      if (c.shape.model_file.front() != '/' && !base_dir.empty()) c.shape.model_file = base_dir + "/" + c.shape.model_file;
      try {
        c.shape.model = std::make_shared<const ShapeModel>(ShapeModel::load(c.shape.model_file));
      } catch (const std::invalid_argument& e) {
        f.fail(std::string("shape.model_file: ") + e.what());
      }
    }
  }
  if (c.candidates.source != ContourSource::kLearned) {
    for (const std::string& path : without_hue) {
      f.fail(path + "hue: missing ([min, max], OpenCV units 0-179; min > max wraps through 0), needed unless "
                    "candidates.source is learned");
    }
  }
  readTunables(f, root, "", c);
  // Every value problem too, not only the ones the reading found (a misread field keeps its valid default).
  const auto invalid = c.validate();
  problems.insert(problems.end(), invalid.begin(), invalid.end());
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid detector configuration", problems));
  return c;
}

DetectorConfig loadDetectorConfigFile(const std::string& path, const std::function<void(YAML::Node&)>& edit) {
  const std::size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : slash == 0 ? "/" : path.substr(0, slash);
  return parseYamlFile(path, "detector configuration", [&](const YAML::Node& root) {
    if (!edit) return parseDetectorConfig(root, dir);
    YAML::Node copy = YAML::Clone(root);
    edit(copy);
    return parseDetectorConfig(copy, dir);
  });
}

DetectorConfig scaledForSearch(const DetectorConfig& config, double scale) {
  DetectorConfig s = config;
  const double k = scale;
  if (k >= 1.0) return s;
  auto scaled = [k](int px) { return px > 1 ? std::max(2, static_cast<int>(std::lround(px * k))) : px; };
  auto odd = [k](int px) { return px > 1 ? std::max(3, static_cast<int>(std::lround(px * k)) | 1) : px; };
  s.colours.blur_px = odd(config.colours.blur_px);
  s.colours.open_kernel_px = scaled(config.colours.open_kernel_px);
  s.colours.close_kernel_px = scaled(config.colours.close_kernel_px);
  s.candidates.blur_kernel_px = odd(config.candidates.blur_kernel_px);
  s.candidates.min_area_px = std::max(1.0, config.candidates.min_area_px * k * k);
  s.candidates.max_area_px = std::max(s.candidates.min_area_px + 1, config.candidates.max_area_px * k * k);
  return s;
}

}  // namespace underwater_stereo
