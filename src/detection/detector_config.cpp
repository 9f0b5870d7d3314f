// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/detector_config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {
namespace {

void parseColour(YamlFields& f, const YAML::Node& node, const std::string& path, ColourClass& c) {
  f.onlyKeys(node, path, {"name", "hue", "saturation", "value", "min_contrast"});
  if (!node.IsMap()) return;
  f.required(node, "name", path, c.name);
  std::vector<double> hue{double(c.hue_min), double(c.hue_max)}, sat{double(c.saturation_min), double(c.saturation_max)},
      val{double(c.value_min), double(c.value_max)};
  if (!node["hue"]) f.fail(path + "hue: missing ([min, max], OpenCV units 0-179; min > max wraps through 0)");
  f.optionalVector(node, "hue", path, hue, 2);
  f.optionalVector(node, "saturation", path, sat, 2);
  f.optionalVector(node, "value", path, val, 2);
  f.optional(node, "min_contrast", path, c.min_contrast);
  c.hue_min = static_cast<int>(hue[0]);
  c.hue_max = static_cast<int>(hue[1]);
  c.saturation_min = static_cast<int>(sat[0]);
  c.saturation_max = static_cast<int>(sat[1]);
  c.value_min = static_cast<int>(val[0]);
  c.value_max = static_cast<int>(val[1]);
}

}  // namespace

std::vector<std::string> DetectorConfig::validate() const {
  std::vector<std::string> p;
  for (const auto& part : {quality.validate(), colours.validate(), candidates.validate(), stereo.validate(),
                           cluster.validate(), shape.validate()}) {
    p.insert(p.end(), part.begin(), part.end());
  }
  if (min_cluster_points < 3) p.push_back("min_cluster_points must be >= 3");
  if (!(search_scale >= 0.1 && search_scale <= 1.0)) p.push_back("search_scale must be in [0.1, 1]");
  return p;
}

DetectorConfig parseDetectorConfig(const YAML::Node& root) {
  std::vector<std::string> problems;
  YamlFields f(problems);
  DetectorConfig c;
  f.onlyKeys(root, "", {"quality", "colours", "grey_world", "mask", "candidates", "stereo", "cluster", "shape",
                        "min_cluster_points", "search_scale"});
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
  if (const YAML::Node list = root["colours"]) {
    if (!list.IsSequence()) {
      f.fail("colours: expected a list of {name, hue, saturation, value}");
    } else {
      for (std::size_t i = 0; i < list.size(); ++i) {
        ColourClass cc;
        parseColour(f, list[i], "colours[" + std::to_string(i) + "].", cc);
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
    else f.fail("candidates.source: '" + source + "' is not colour_mask or grey_threshold");
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
  f.optional(root, "min_cluster_points", "", c.min_cluster_points);
  f.optional(root, "search_scale", "", c.search_scale);
  // Every value problem too, not only the ones the reading found (a misread field keeps its valid default).
  const auto invalid = c.validate();
  problems.insert(problems.end(), invalid.begin(), invalid.end());
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid detector configuration", problems));
  return c;
}

DetectorConfig loadDetectorConfigFile(const std::string& path) {
  return parseYamlFile(path, "detector configuration", parseDetectorConfig);
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
