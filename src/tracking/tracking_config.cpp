// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/tracking/tracking_config.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <set>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {
namespace {

void requirePositive(std::vector<std::string>& p, const std::string& name, double value) {
  if (!(value > 0.0 && std::isfinite(value))) p.push_back(name + " must be > 0 (got " + std::to_string(value) + ")");
}

void requireNonNegative(std::vector<std::string>& p, const std::string& name, double value) {
  if (!(value >= 0.0 && std::isfinite(value))) p.push_back(name + " must be >= 0 (got " + std::to_string(value) + ")");
}

}  // namespace

std::vector<std::string> TrackingConfig::validate() const {
  std::vector<std::string> p;
  std::set<std::string> names;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const Target& t = targets[i];
    const std::string path = "targets[" + std::to_string(i) + "].";
    if (t.name.empty()) p.push_back(path + "name: empty");
    if (!names.insert(t.name).second) p.push_back(path + "name: '" + t.name + "' used twice");
    if (t.colour.empty()) p.push_back(path + "colour: empty");
    requirePositive(p, path + "size_m", t.size_m);
    if (!(t.size_tolerance > 0.0 && t.size_tolerance < 1.0)) p.push_back(path + "size_tolerance must be in (0, 1)");
  }
  if (targets_only && targets.empty()) p.push_back("targets_only: true needs at least one target");
  requireNonNegative(p, "tracking.range_sigma_fraction", range_sigma_fraction);
  requireNonNegative(p, "tracking.lateral_sigma_fraction", lateral_sigma_fraction);
  requirePositive(p, "tracking.min_sigma_m", min_sigma_m);
  if (!(cut_by_border_sigma_scale >= 1.0 && std::isfinite(cut_by_border_sigma_scale))) {
    p.push_back("tracking.cut_by_border_sigma_scale must be >= 1, a part being no surer than the whole (got " +
                std::to_string(cut_by_border_sigma_scale) + ")");
  }
  requirePositive(p, "tracking.acceleration_sigma_mps2", acceleration_sigma_mps2);
  requirePositive(p, "tracking.initial_speed_sigma_mps", initial_speed_sigma_mps);
  requirePositive(p, "tracking.gate_chi2", gate_chi2);
  if (confirm_hits < 1) p.push_back("tracking.confirm_hits must be >= 1");
  if (tentative_max_misses < 1) p.push_back("tracking.tentative_max_misses must be >= 1");
  if (max_misses < 1) p.push_back("tracking.max_misses must be >= 1");
  requireNonNegative(p, "tracking.view_margin_px", view_margin_px);
  requireNonNegative(p, "tracking.occlusion_margin_m", occlusion_margin_m);
  requirePositive(p, "tracking.max_camera_speed_mps", max_camera_speed_mps);
  requirePositive(p, "tracking.max_camera_turn_rate_dps", max_camera_turn_rate_dps);
  requireNonNegative(p, "tracking.max_backwards_s", max_backwards_s);
  return p;
}

const Target* TrackingConfig::target(const std::string& name) const {
  for (const Target& t : targets) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

TrackingConfig parseTrackingConfig(const YAML::Node& root) {
  std::vector<std::string> problems;
  YamlFields f(problems);
  TrackingConfig c;
  f.onlyKeys(root, "", {"targets", "targets_only", "tracking"});
  if (!root.IsMap()) throw std::invalid_argument(joinProblems("invalid tracking configuration", problems));
  f.optional(root, "targets_only", "", c.targets_only);
  if (const YAML::Node list = root["targets"]) {
    if (!list.IsSequence()) f.fail("targets: expected a list of {name, colour, shape, size_m, size_tolerance}");
    for (std::size_t i = 0; list.IsSequence() && i < list.size(); ++i) {
      const std::string path = "targets[" + std::to_string(i) + "].";
      const YAML::Node t = list[i];
      f.onlyKeys(t, path, {"name", "colour", "shape", "size_m", "size_tolerance"});
      if (!t.IsMap()) continue;
      Target target;
      f.required(t, "name", path, target.name);
      f.required(t, "colour", path, target.colour);
      std::string shape;
      f.optional(t, "shape", path, shape);
      try {
        if (!shape.empty()) target.shape = shapeFromName(shape, path + "shape");
      } catch (const std::invalid_argument& e) {
        f.fail(e.what());
      }
      f.required(t, "size_m", path, target.size_m);
      f.optional(t, "size_tolerance", path, target.size_tolerance);
      c.targets.push_back(target);
    }
  }
  if (const YAML::Node t = root["tracking"]) {
    const std::string path = "tracking.";
    f.onlyKeys(t, path, {"reject_wrong_size", "match_shape", "range_sigma_fraction", "lateral_sigma_fraction",
                         "min_sigma_m", "cut_by_border_sigma_scale", "acceleration_sigma_mps2",
                         "initial_speed_sigma_mps", "gate_chi2", "confirm_hits", "tentative_max_misses", "max_misses",
                         "view_margin_px", "occlusion_margin_m", "max_camera_speed_mps", "max_camera_turn_rate_dps",
                         "max_backwards_s"});
    if (t.IsMap()) {
      f.optional(t, "reject_wrong_size", path, c.reject_wrong_size);
      f.optional(t, "match_shape", path, c.match_shape);
      f.optional(t, "range_sigma_fraction", path, c.range_sigma_fraction);
      f.optional(t, "lateral_sigma_fraction", path, c.lateral_sigma_fraction);
      f.optional(t, "min_sigma_m", path, c.min_sigma_m);
      f.optional(t, "cut_by_border_sigma_scale", path, c.cut_by_border_sigma_scale);
      f.optional(t, "acceleration_sigma_mps2", path, c.acceleration_sigma_mps2);
      f.optional(t, "initial_speed_sigma_mps", path, c.initial_speed_sigma_mps);
      f.optional(t, "gate_chi2", path, c.gate_chi2);
      f.optional(t, "confirm_hits", path, c.confirm_hits);
      f.optional(t, "tentative_max_misses", path, c.tentative_max_misses);
      f.optional(t, "max_misses", path, c.max_misses);
      f.optional(t, "view_margin_px", path, c.view_margin_px);
      f.optional(t, "occlusion_margin_m", path, c.occlusion_margin_m);
      f.optional(t, "max_camera_speed_mps", path, c.max_camera_speed_mps);
      f.optional(t, "max_camera_turn_rate_dps", path, c.max_camera_turn_rate_dps);
      f.optional(t, "max_backwards_s", path, c.max_backwards_s);
    }
  }
  const std::vector<std::string> invalid = c.validate();
  problems.insert(problems.end(), invalid.begin(), invalid.end());
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid tracking configuration", problems));
  return c;
}

TrackingConfig loadTrackingConfigFile(const std::string& path) {
  return parseYamlFile(path, "tracking configuration", parseTrackingConfig);
}

}  // namespace underwater_stereo
