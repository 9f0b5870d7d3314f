// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/sim/scene.h"

#include <opencv2/core.hpp>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {
namespace sim {
namespace {

void parseMotion(YamlFields& f, const YAML::Node& node, const std::string& path, Motion& m) {
  if (!node) return;
  f.onlyKeys(node, path,
             {"velocity_mps", "yaw_rate_dps", "yaw_amplitude_deg", "yaw_period_s", "bob_amplitude_m", "bob_period_s"});
  f.optionalVector3(node, "velocity_mps", path, m.velocity_mps);
  f.optional(node, "yaw_rate_dps", path, m.yaw_rate_dps);
  f.optional(node, "yaw_amplitude_deg", path, m.yaw_amplitude_deg);
  f.optional(node, "yaw_period_s", path, m.yaw_period_s);
  f.optional(node, "bob_amplitude_m", path, m.bob_amplitude_m);
  f.optional(node, "bob_period_s", path, m.bob_period_s);
}

bool parseShape(const std::string& name, ShapeType& shape) {
  if (name == "sphere") shape = ShapeType::kSphere;
  else if (name == "cylinder") shape = ShapeType::kCylinder;
  else if (name == "box") shape = ShapeType::kBox;
  else if (name == "plane" || name == "panel") shape = ShapeType::kPanel;
  else return false;
  return true;
}

SceneObject parseObject(YamlFields& f, const YAML::Node& node, const std::string& path) {
  SceneObject o;
  f.onlyKeys(node, path, {"name", "shape", "colour", "albedo", "texture", "specular", "shininess", "position_m", "rpy_deg", "diameter_m",
                          "length_m", "size_m", "motion"});
  if (!node.IsMap()) return o;
  f.required(node, "name", path, o.name);
  std::string shape;
  f.required(node, "shape", path, shape);
  if (!shape.empty() && !parseShape(shape, o.shape)) {
    f.fail(path + "shape: '" + shape + "' is not one of sphere, cylinder, box, plane");
  }
  f.required(node, "colour", path, o.colour);
  f.optionalVector3(node, "albedo", path, o.albedo);
  f.optional(node, "texture", path, o.texture);
  f.optional(node, "specular", path, o.specular);
  f.optional(node, "shininess", path, o.shininess);
  if (!node["position_m"]) f.fail(path + "position_m: missing");
  f.optionalVector3(node, "position_m", path, o.position_m);
  f.optionalVector3(node, "rpy_deg", path, o.rpy_deg);
  switch (o.shape) {
    case ShapeType::kSphere: {
      double d = 0.0;
      f.required(node, "diameter_m", path, d);
      o.size_m = Eigen::Vector3d(d, d, d);
      break;
    }
    case ShapeType::kCylinder: {
      double d = 0.0, length = 0.0;
      f.required(node, "diameter_m", path, d);
      f.required(node, "length_m", path, length);
      o.size_m = Eigen::Vector3d(d, d, length);
      break;
    }
    case ShapeType::kBox:
      if (!node["size_m"]) f.fail(path + "size_m: missing (box edges [x, y, z])");
      f.optionalVector3(node, "size_m", path, o.size_m);
      break;
    case ShapeType::kPanel: {
      std::vector<double> wh{0.0, 0.0};
      if (!node["size_m"]) f.fail(path + "size_m: missing (panel [width, height])");
      f.optionalVector(node, "size_m", path, wh, 2);
      o.size_m = Eigen::Vector3d(wh[0], wh[1], 0.0);
      break;
    }
  }
  parseMotion(f, node["motion"], path + "motion.", o.motion);
  return o;
}

void requireRange(std::vector<std::string>& problems, const std::string& name, double value, double lo, double hi) {
  if (!(value >= lo && value <= hi)) {
    problems.push_back(name + " = " + cv::format("%g is outside [%g, %g]", value, lo, hi));
  }
}

void requireRange3(std::vector<std::string>& problems, const std::string& name, const Eigen::Vector3d& v, double lo,
                   double hi) {
  for (int i = 0; i < 3; ++i) requireRange(problems, name + "[" + std::to_string(i) + "]", v[i], lo, hi);
}

/// A motion any vehicle or object in a pool could have (a NaN or a runaway value renders nonsense truth).
void requireMotion(std::vector<std::string>& problems, const std::string& name, const Motion& m) {
  requireRange3(problems, name + "velocity_mps", m.velocity_mps, -100, 100);
  requireRange(problems, name + "yaw_rate_dps", m.yaw_rate_dps, -3600, 3600);
  requireRange(problems, name + "yaw_amplitude_deg", m.yaw_amplitude_deg, -360, 360);
  requireRange(problems, name + "yaw_period_s", m.yaw_period_s, 0.1, 1e6);
  requireRange(problems, name + "bob_amplitude_m", m.bob_amplitude_m, -100, 100);
  requireRange(problems, name + "bob_period_s", m.bob_period_s, 0.1, 1e6);
}

}  // namespace

std::string shapeName(ShapeType shape) {
  switch (shape) {
    case ShapeType::kSphere: return "sphere";
    case ShapeType::kCylinder: return "cylinder";
    case ShapeType::kBox: return "box";
    case ShapeType::kPanel: return "plane";
  }
  return "unknown";
}

std::vector<std::string> Scene::validate() const {
  std::vector<std::string> p;
  requireRange(p, "rig.width", rig.width, 16, 8192);
  requireRange(p, "rig.height", rig.height, 16, 8192);
  // Up to 1 mm: small test and probe renders keep the field of view with few, large pixels.
  requireRange(p, "rig.pixel_size_um", rig.pixel_size_um, 0.5, 1000);
  requireRange(p, "rig.focal_length_mm", rig.focal_length_mm, 1, 100);
  requireRange(p, "rig.water_focal_factor", rig.water_focal_factor, 1, 2);
  requireRange(p, "rig.baseline_m", rig.baseline_m, 0.01, 2);
  requireRange3(p, "rig.right_rotation_deg", rig.right_rotation_deg, -10, 10);
  requireRange3(p, "rig.right_offset_m", rig.right_offset_m, -0.05, 0.05);
  if (rig.left_distortion.size() != 5) p.push_back("rig.left_distortion: needs 5 numbers (k1 k2 p1 p2 k3)");
  if (rig.right_distortion.size() != 5) p.push_back("rig.right_distortion: needs 5 numbers (k1 k2 p1 p2 k3)");
  for (const auto* d : {&rig.left_distortion, &rig.right_distortion}) {
    for (double k : *d) requireRange(p, "rig distortion coefficient", k, -1, 1);
  }
  requireRange(p, "rig.principal_offset_px", rig.principal_offset_px, -200, 200);
  requireRange3(p, "water.attenuation_per_m", water.attenuation_per_m, 0, 5);
  requireRange3(p, "water.veiling_light", water.veiling_light, 0, 1);
  requireRange(p, "water.veiling_gradient", water.veiling_gradient, 0, 2);
  requireRange3(p, "light.downwelling", light.downwelling, 0, 10);
  requireRange(p, "light.ambient", light.ambient, 0, 1);
  requireRange3(p, "light.sun_direction", light.sun_direction, -1, 1);
  if (!(light.sun_direction.y() > 0.05 * light.sun_direction.norm())) {
    p.push_back("light.sun_direction: must point down (y > 0): the sun is above the water");
  }
  requireRange(p, "light.caustics", light.caustics, 0, 1);
  requireRange(p, "light.caustics_scale_m", light.caustics_scale_m, 0.01, 10);
  requireRange3(p, "light.lamp_colour", light.lamp_colour, 0, 2);
  requireRange(p, "light.lamp_intensity", light.lamp_intensity, 0, 100);
  requireRange(p, "light.exposure", light.exposure, 0.01, 100);
  requireRange(p, "seabed.depth_m", seabed.depth_m, 0.1, 1000);
  requireRange3(p, "seabed.albedo", seabed.albedo, 0, 1);
  requireRange(p, "seabed.texture", seabed.texture, 0, 1);
  requireRange(p, "seabed.texture_scale_m", seabed.texture_scale_m, 0.001, 100);
  if (sensor.encoding != "bayer_rggb8" && sensor.encoding != "bgr8") {
    p.push_back("sensor.encoding: '" + sensor.encoding + "' is not bayer_rggb8 or bgr8");
  }
  requireRange(p, "sensor.noise_sigma", sensor.noise_sigma, 0, 100);
  requireRange(p, "sensor.blur_sigma_px", sensor.blur_sigma_px, 0, 20);
  requireRange(p, "sensor.gamma", sensor.gamma, 0.2, 5);
  requireRange3(p, "sensor.white_balance", sensor.white_balance, 0.1, 10);
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const SceneObject& o = objects[i];
    const std::string n = "objects[" + std::to_string(i) + "] (" + o.name + ").";
    requireRange3(p, n + "albedo", o.albedo, 0, 1);
    requireRange(p, n + "texture", o.texture, 0, 1);
    requireRange(p, n + "specular", o.specular, 0, 1);
    requireRange(p, n + "shininess", o.shininess, 1, 5000);
    requireRange3(p, n + "position_m", o.position_m, -1000, 1000);
    requireRange3(p, n + "rpy_deg", o.rpy_deg, -3600, 3600);
    const int extents = o.shape == ShapeType::kPanel ? 2 : 3;
    for (int k = 0; k < extents; ++k) requireRange(p, n + "size_m[" + std::to_string(k) + "]", o.size_m[k], 0.005, 50);
    requireMotion(p, n + "motion.", o.motion);
    if (o.colour.empty()) p.push_back(n + "colour: empty");
    for (std::size_t j = 0; j < i; ++j) {
      if (objects[j].name == o.name) p.push_back(n + "name: '" + o.name + "' is used twice");
    }
  }
  requireMotion(p, "camera_motion.", camera_motion);
  return p;
}

Scene parseScene(const YAML::Node& root) {
  std::vector<std::string> problems;
  YamlFields f(problems);
  Scene s;
  f.onlyKeys(root, "", {"name", "rig", "water", "light", "seabed", "sensor", "camera_motion", "objects"});
  if (!root.IsMap()) throw std::invalid_argument(joinProblems("invalid scene", problems));
  f.optional(root, "name", "", s.name);
  if (const YAML::Node r = root["rig"]) {
    f.onlyKeys(r, "rig.", {"width", "height", "pixel_size_um", "focal_length_mm", "water_focal_factor", "baseline_m",
                           "right_rotation_deg", "right_offset_m", "left_distortion", "right_distortion",
                           "principal_offset_px"});
    f.optional(r, "width", "rig.", s.rig.width);
    f.optional(r, "height", "rig.", s.rig.height);
    f.optional(r, "pixel_size_um", "rig.", s.rig.pixel_size_um);
    f.optional(r, "focal_length_mm", "rig.", s.rig.focal_length_mm);
    f.optional(r, "water_focal_factor", "rig.", s.rig.water_focal_factor);
    f.optional(r, "baseline_m", "rig.", s.rig.baseline_m);
    f.optionalVector3(r, "right_rotation_deg", "rig.", s.rig.right_rotation_deg);
    f.optionalVector3(r, "right_offset_m", "rig.", s.rig.right_offset_m);
    f.optionalVector(r, "left_distortion", "rig.", s.rig.left_distortion, 5);
    f.optionalVector(r, "right_distortion", "rig.", s.rig.right_distortion, 5);
    f.optional(r, "principal_offset_px", "rig.", s.rig.principal_offset_px);
  }
  if (const YAML::Node w = root["water"]) {
    f.onlyKeys(w, "water.", {"attenuation_per_m", "veiling_light", "veiling_gradient"});
    f.optionalVector3(w, "attenuation_per_m", "water.", s.water.attenuation_per_m);
    f.optionalVector3(w, "veiling_light", "water.", s.water.veiling_light);
    f.optional(w, "veiling_gradient", "water.", s.water.veiling_gradient);
  }
  if (const YAML::Node l = root["light"]) {
    f.onlyKeys(l, "light.", {"downwelling", "ambient", "sun_direction", "caustics", "caustics_scale_m",
                             "lamp_intensity", "lamp_colour", "exposure"});
    f.optionalVector3(l, "downwelling", "light.", s.light.downwelling);
    f.optional(l, "ambient", "light.", s.light.ambient);
    f.optionalVector3(l, "sun_direction", "light.", s.light.sun_direction);
    f.optional(l, "caustics", "light.", s.light.caustics);
    f.optional(l, "caustics_scale_m", "light.", s.light.caustics_scale_m);
    f.optional(l, "lamp_intensity", "light.", s.light.lamp_intensity);
    f.optionalVector3(l, "lamp_colour", "light.", s.light.lamp_colour);
    f.optional(l, "exposure", "light.", s.light.exposure);
  }
  if (const YAML::Node b = root["seabed"]) {
    f.onlyKeys(b, "seabed.", {"enabled", "depth_m", "albedo", "texture", "texture_scale_m"});
    f.optional(b, "enabled", "seabed.", s.seabed.enabled);
    f.optional(b, "depth_m", "seabed.", s.seabed.depth_m);
    f.optionalVector3(b, "albedo", "seabed.", s.seabed.albedo);
    f.optional(b, "texture", "seabed.", s.seabed.texture);
    f.optional(b, "texture_scale_m", "seabed.", s.seabed.texture_scale_m);
  }
  if (const YAML::Node n = root["sensor"]) {
    f.onlyKeys(n, "sensor.", {"encoding", "noise_sigma", "blur_sigma_px", "gamma", "white_balance", "seed"});
    f.optional(n, "encoding", "sensor.", s.sensor.encoding);
    f.optional(n, "noise_sigma", "sensor.", s.sensor.noise_sigma);
    f.optional(n, "blur_sigma_px", "sensor.", s.sensor.blur_sigma_px);
    f.optional(n, "gamma", "sensor.", s.sensor.gamma);
    f.optionalVector3(n, "white_balance", "sensor.", s.sensor.white_balance);
    f.optional(n, "seed", "sensor.", s.sensor.seed);
  }
  parseMotion(f, root["camera_motion"], "camera_motion.", s.camera_motion);
  std::vector<std::string> unparsed;  // "objects[i] (" of each object with a field that did not parse
  if (const YAML::Node objs = root["objects"]) {
    if (!objs.IsSequence()) {
      f.fail("objects: expected a list");
    } else {
      for (std::size_t i = 0; i < objs.size(); ++i) {
        const std::size_t before = problems.size();
        s.objects.push_back(parseObject(f, objs[i], "objects[" + std::to_string(i) + "]."));
        if (problems.size() > before) unparsed.push_back("objects[" + std::to_string(i) + "] (");
      }
    }
  }
  // Every value is checked along with what did not parse, so that one reading lists every problem. A field that did
  // not parse keeps its (valid) default, except in an object missing a required field (its colour empty, its size
  // zero): such an object's values are not checked again, its parse problems name it.
  for (const std::string& v : s.validate()) {
    if (std::none_of(unparsed.begin(), unparsed.end(), [&](const std::string& o) { return v.rfind(o, 0) == 0; })) {
      problems.push_back(v);
    }
  }
  // The head's images are Bayer mosaics (2 x 2 pixels a cell), which the detector reads only at even sizes. Checked
  // for scene files, not in validate(): the sampler's exposure renders at a fraction of the size, odd or not.
  if (s.rig.width % 2 != 0 || s.rig.height % 2 != 0) {
    problems.push_back("rig.width and rig.height must be even (the head renders a Bayer mosaic), got " +
                       std::to_string(s.rig.width) + "x" + std::to_string(s.rig.height));
  }
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid scene", problems));
  return s;
}

Scene loadSceneFile(const std::string& path) { return parseYamlFile(path, "scene file", parseScene); }

}  // namespace sim
}  // namespace underwater_stereo
