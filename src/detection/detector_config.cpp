// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/detector_config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {
namespace {

/// Reads one colour class; returns false when it has no hue range (only a learnt colour model needs none).
bool parseColour(YamlFields& f, const YAML::Node& node, const std::string& path, ColourClass& c) {
  f.onlyKeys(node, path, {"name", "hue", "saturation", "value", "min_contrast", "size_m"});
  if (!node.IsMap()) return true;
  f.required(node, "name", path, c.name);
  std::vector<double> hue{double(c.hue_min), double(c.hue_max)}, sat{double(c.saturation_min), double(c.saturation_max)},
      val{double(c.value_min), double(c.value_max)};
  f.optionalVector(node, "hue", path, hue, 2);
  f.optionalVector(node, "saturation", path, sat, 2);
  f.optionalVector(node, "value", path, val, 2);
  f.optional(node, "min_contrast", path, c.min_contrast);
  std::vector<double> size{c.min_size_m, c.max_size_m};
  f.optionalVector(node, "size_m", path, size, 2);
  c.min_size_m = size[0];
  c.max_size_m = size[1];
  c.hue_min = static_cast<int>(hue[0]);
  c.hue_max = static_cast<int>(hue[1]);
  c.saturation_min = static_cast<int>(sat[0]);
  c.saturation_max = static_cast<int>(sat[1]);
  c.value_min = static_cast<int>(val[0]);
  c.value_max = static_cast<int>(val[1]);
  return static_cast<bool>(node["hue"]);
}

}  // namespace

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
  }
  if (min_cluster_points < 3) p.push_back("min_cluster_points must be >= 3");
  if (!(search_scale >= 0.1 && search_scale <= 1.0)) p.push_back("search_scale must be in [0.1, 1]");
  return p;
}

DetectorConfig parseDetectorConfig(const YAML::Node& root, const std::string& base_dir) {
  std::vector<std::string> problems;
  YamlFields f(problems);
  DetectorConfig c;
  f.onlyKeys(root, "", {"quality", "colours", "grey_world", "mask", "candidates", "colour_model", "stereo", "cluster",
                        "shape", "min_cluster_points", "search_scale"});
  if (!root.IsMap()) throw std::invalid_argument(joinProblems("invalid detector configuration", problems));
  if (const YAML::Node q = root["quality"]) {
    f.onlyKeys(q, "quality.", {"too_dark_below", "too_bright_above", "enhance_below", "dark_pixel_value",
                               "bright_pixel_value", "clahe_clip_limit", "clahe_tiles"});
    f.optional(q, "too_dark_below", "quality.", c.quality.too_dark_below);
    f.optional(q, "too_bright_above", "quality.", c.quality.too_bright_above);
    f.optional(q, "enhance_below", "quality.", c.quality.enhance_below);
    f.optional(q, "dark_pixel_value", "quality.", c.quality.dark_pixel_value);
    f.optional(q, "bright_pixel_value", "quality.", c.quality.bright_pixel_value);
    f.optional(q, "clahe_clip_limit", "quality.", c.quality.clahe_clip_limit);
    f.optional(q, "clahe_tiles", "quality.", c.quality.clahe_tiles);
  }
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
    f.onlyKeys(n, "candidates.", {"source", "threshold", "fixed_threshold", "dark_objects", "blur_kernel_px",
                                  "min_area_px", "max_area_px", "min_colour_fraction", "max_candidates"});
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
    f.optional(n, "fixed_threshold", "candidates.", c.candidates.fixed_threshold);
    f.optional(n, "dark_objects", "candidates.", c.candidates.dark_objects);
    f.optional(n, "blur_kernel_px", "candidates.", c.candidates.blur_kernel_px);
    f.optional(n, "min_area_px", "candidates.", c.candidates.min_area_px);
    f.optional(n, "max_area_px", "candidates.", c.candidates.max_area_px);
    f.optional(n, "min_colour_fraction", "candidates.", c.candidates.min_colour_fraction);
    f.optional(n, "max_candidates", "candidates.", c.candidates.max_candidates);
  }
  if (const YAML::Node m = root["colour_model"]; m && !m.IsMap()) {
    f.fail("colour_model: expected a map of {file, min_confidence, max_overlap, background_scale, levels, max_proposals}");
  } else if (m) {
    f.onlyKeys(m, "colour_model.", {"file", "min_confidence", "max_overlap", "background_scale", "levels", "max_proposals"});
    LearnedColourConfig& l = c.learned;
    f.optional(m, "file", "colour_model.", l.file);
    f.optional(m, "min_confidence", "colour_model.", l.min_confidence);
    f.optional(m, "max_overlap", "colour_model.", l.max_overlap);
    f.optional(m, "background_scale", "colour_model.", l.water.background_scale);
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
    f.optional(m, "max_proposals", "colour_model.", l.proposals.max_proposals);
    if (!l.file.empty()) {
      if (l.file.front() != '/' && !base_dir.empty()) l.file = base_dir + "/" + l.file;
      try {
        l.model = std::make_shared<const ColourModel>(ColourModel::load(l.file));
      } catch (const std::invalid_argument& e) {
        f.fail(std::string("colour_model.file: ") + e.what());
      }
    }
  }
  if (const YAML::Node s = root["stereo"]) {
    f.onlyKeys(s, "stereo.", {"min_depth_m", "max_depth_m", "block_size", "uniqueness_ratio", "margin_px", "erode_px",
                              "max_points"});
    f.optional(s, "min_depth_m", "stereo.", c.stereo.min_depth_m);
    f.optional(s, "max_depth_m", "stereo.", c.stereo.max_depth_m);
    f.optional(s, "block_size", "stereo.", c.stereo.block_size);
    f.optional(s, "uniqueness_ratio", "stereo.", c.stereo.uniqueness_ratio);
    f.optional(s, "margin_px", "stereo.", c.stereo.margin_px);
    f.optional(s, "erode_px", "stereo.", c.stereo.erode_px);
    f.optional(s, "max_points", "stereo.", c.stereo.max_points);
  }
  if (const YAML::Node k = root["cluster"]) {
    f.onlyKeys(k, "cluster.", {"eps_m", "min_points"});
    f.optional(k, "eps_m", "cluster.", c.cluster.eps_m);
    f.optional(k, "min_points", "cluster.", c.cluster.min_points);
  }
  if (const YAML::Node s = root["shape"]) {
    f.onlyKeys(s, "shape.", {"min_points", "plane_preference", "min_elongation", "box_face_contrast"});
    f.optional(s, "min_points", "shape.", c.shape.min_points);
    f.optional(s, "plane_preference", "shape.", c.shape.plane_preference);
    f.optional(s, "box_face_contrast", "shape.", c.shape.box_face_contrast);
    f.optional(s, "min_elongation", "shape.", c.shape.min_elongation);
  }
  if (c.candidates.source != ContourSource::kLearned) {
    for (const std::string& path : without_hue) {
      f.fail(path + "hue: missing ([min, max], OpenCV units 0-179; min > max wraps through 0), needed unless "
                    "candidates.source is learned");
    }
  }
  f.optional(root, "min_cluster_points", "", c.min_cluster_points);
  f.optional(root, "search_scale", "", c.search_scale);
  // Every value problem too, not only the ones the reading found (a misread field keeps its valid default).
  const auto invalid = c.validate();
  problems.insert(problems.end(), invalid.begin(), invalid.end());
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid detector configuration", problems));
  return c;
}

DetectorConfig loadDetectorConfigFile(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "" : path.substr(0, slash);
  return parseYamlFile(path, "detector configuration",
                       [&dir](const YAML::Node& root) { return parseDetectorConfig(root, dir.empty() ? "." : dir); });
}

DetectorConfig scaledForSearch(const DetectorConfig& config) {
  DetectorConfig s = config;
  const double k = config.search_scale;
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
