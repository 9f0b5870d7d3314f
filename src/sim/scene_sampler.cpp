// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/sim/scene_sampler.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "underwater_stereo/common/stereo_calibration.h"
#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/sim/renderer.h"
#include "underwater_stereo/sim/stereo_rig.h"

namespace underwater_stereo {
namespace sim {
namespace {

/// Uniform numbers from the fully specified mt19937_64 (std:: distributions differ between libraries).
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : engine_(seed * 0x9E3779B97F4A7C15ULL + 0x2545F4914F6CDD1DULL) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double uniform(const std::pair<double, double>& r) { return uniform(r.first, r.second); }
  int integer(int lo, int hi) { return std::min(hi, lo + static_cast<int>(uniform(0.0, hi - lo + 1.0))); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  double logUniform(double lo, double hi) { return std::exp(uniform(std::log(lo), std::log(hi))); }
  std::uint64_t bits() { return engine_(); }

 private:
  std::mt19937_64 engine_;
};

// Absorption [1/m] of three water types, linear r, g, b: clear ocean absorbs red; coastal water's
// phytoplankton absorbs blue too; dissolved organic matter (brown, "tea") absorbs blue most.
const Eigen::Vector3d kAbsorptionBlue(0.38, 0.05, 0.03);
const Eigen::Vector3d kAbsorptionGreen(0.42, 0.08, 0.18);
const Eigen::Vector3d kAbsorptionBrown(0.45, 0.20, 0.50);
// Scattering [1/m] at turbidity 0 and 1, about equal in all channels (a slight blue excess).
constexpr double kScatterClear = 0.02, kScatterMurky = 0.25;
const Eigen::Vector3d kScatterTint(0.9, 1.0, 1.1);

Eigen::Vector3d absorption(double water_type) {
  if (water_type <= 1.0) return (1.0 - water_type) * kAbsorptionBlue + water_type * kAbsorptionGreen;
  return (2.0 - water_type) * kAbsorptionGreen + (water_type - 1.0) * kAbsorptionBrown;
}

const ColourFamily& family(const std::string& name) {
  for (const auto& f : colourFamilies()) {
    if (f.name == name) return f;
  }
  throw std::invalid_argument("no colour family '" + name + "'");
}

/// Shape, size and orientation of one object; largest extent within config.size_m.
SceneObject drawBody(Draw& draw, const SceneSamplerConfig& config) {
  SceneObject o;
  o.shape = static_cast<ShapeType>(draw.integer(0, 3));
  const double largest = draw.uniform(config.size_m);
  const double lo = config.size_m.first;
  switch (o.shape) {
    case ShapeType::kSphere: o.size_m = Eigen::Vector3d::Constant(largest); break;
    case ShapeType::kCylinder: {
      // Tubes and drums: the largest extent is the length or the diameter.
      const double other = draw.uniform(std::min(0.06, largest), largest);
      o.size_m = draw.chance(0.7) ? Eigen::Vector3d(other, other, largest) : Eigen::Vector3d(largest, largest, other);
      break;
    }
    case ShapeType::kBox:
      o.size_m = Eigen::Vector3d(largest, draw.uniform(std::min(lo, largest), largest),
                                 draw.uniform(std::min(lo, largest), largest));
      break;
    case ShapeType::kPanel:
      o.size_m = Eigen::Vector3d(largest, draw.uniform(std::min(lo, largest), largest), 0.0);
      if (draw.chance(0.5)) std::swap(o.size_m.x(), o.size_m.y());
      break;
  }
  if (o.shape == ShapeType::kPanel) {
    // A panel seen edge-on shows nothing: its normal stays within 60 deg of the line of sight.
    o.rpy_deg = Eigen::Vector3d(draw.uniform(-60, 60), draw.uniform(-60, 60), draw.uniform(-180, 180));
  } else {
    o.rpy_deg = Eigen::Vector3d(draw.uniform(-180, 180), draw.uniform(-90, 90), draw.uniform(-180, 180));
  }
  return o;
}

void drawSurface(Draw& draw, const ColourFamily& f, SceneObject& o) {
  o.colour = f.name;
  o.albedo = albedoFromHsv(draw.uniform(f.hue_deg), draw.uniform(f.saturation), draw.uniform(f.value));
  o.texture = draw.uniform(0.02, 0.25);
  o.specular = draw.chance(0.6) ? draw.uniform(0.05, 0.5) : 0.0;
  o.shininess = draw.logUniform(10.0, 300.0);
}

/// Where the object's centre goes: a pixel and a range. One in four centres may lie near or up to 8 % beyond
/// the border (so the object is cut); the others stay 5 % inside it (near, large objects are cut all the same).
Eigen::Vector3d drawPosition(Draw& draw, const SceneSamplerConfig& config, const StereoRig& rig, double radius) {
  const double margin = draw.chance(config.border_probability) ? -0.08 : 0.05;
  const double u = draw.uniform(margin, 1.0 - margin) * config.width;
  const double v = draw.uniform(margin, 1.0 - margin) * config.height;
  const cv::Matx33d& k = rig.left().K;
  const Eigen::Vector3d ray = Eigen::Vector3d((u - k(0, 2)) / k(0, 0), (v - k(1, 2)) / k(1, 1), 1.0).normalized();
  const double near = std::max(config.range_m.first, radius + 0.25);  // never around the camera
  return ray * draw.uniform(near, std::max(near, config.range_m.second));
}

bool fits(const SceneObject& o, const std::vector<SceneObject>& placed, const Scene& scene) {
  const double r = boundingRadius(o);
  if (scene.seabed.enabled && o.position_m.y() + r > scene.seabed.depth_m - 0.01) return false;
  for (const auto& p : placed) {
    if ((p.position_m - o.position_m).norm() < r + boundingRadius(p) + 0.02) return false;
  }
  return true;
}

void drawWaterAndLight(Draw& draw, const SceneSamplerConfig& config, SampledScene& out) {
  Scene& s = out.scene;
  out.water_type = draw.uniform(config.water_type);
  out.turbidity = draw.uniform(config.turbidity);
  const Eigen::Vector3d a = absorption(out.water_type);
  const Eigen::Vector3d b = (kScatterClear + (kScatterMurky - kScatterClear) * out.turbidity) * kScatterTint;
  s.water.attenuation_per_m = a + b;
  // Sunlight after the water above the scene (diffuse attenuation: absorption plus part of the scattering).
  const double depth_below_surface_m = draw.uniform(0.5, 6.0);
  const Eigen::Vector3d sun_colour(1.0, draw.uniform(0.95, 1.0), draw.uniform(0.85, 1.0));
  s.light.downwelling = draw.uniform(0.6, 1.6) * sun_colour.cwiseProduct(
                                                     (-(a + 0.3 * b) * depth_below_surface_m).array().exp().matrix());
  // Veiling light: single scattering of that light, b / c of it per channel.
  s.water.veiling_light =
      (draw.uniform(0.35, 0.6) * s.light.downwelling.cwiseProduct(b.cwiseQuotient(s.water.attenuation_per_m)))
          .cwiseMin(1.0);
  s.water.veiling_gradient = draw.uniform(0.2, 1.0);
  s.light.ambient = draw.uniform(0.2, 0.5);
  const double zenith = draw.uniform(0.0, 35.0) * M_PI / 180.0, azimuth = draw.uniform(-M_PI, M_PI);
  s.light.sun_direction = Eigen::Vector3d(std::sin(zenith) * std::cos(azimuth), std::cos(zenith),
                                          std::sin(zenith) * std::sin(azimuth));
  s.light.caustics = draw.uniform(0.0, 1.0) * (1.0 - 0.7 * out.turbidity);
  s.light.caustics_scale_m = draw.uniform(0.1, 0.5);
  s.light.lamp_intensity = draw.chance(0.6) ? draw.uniform(0.2, 1.5) : 0.0;
  s.light.lamp_colour = Eigen::Vector3d(1.0, draw.uniform(0.9, 1.0), draw.uniform(0.75, 1.05));

  s.seabed.enabled = draw.chance(0.85);
  s.seabed.depth_m = draw.uniform(1.0, 5.0);
  const Eigen::Vector3d beds[] = {{0.55, 0.5, 0.4}, {0.3, 0.28, 0.2}, {0.35, 0.36, 0.37}};
  s.seabed.albedo = (beds[draw.integer(0, 2)] * draw.uniform(0.5, 1.2)).cwiseMin(1.0);
  s.seabed.texture = draw.uniform(0.2, 0.7);
  s.seabed.texture_scale_m = draw.uniform(0.05, 0.4);

  s.sensor.encoding = "bayer_rggb8";
  s.sensor.noise_sigma = draw.uniform(0.5, 4.0);
  s.sensor.blur_sigma_px = draw.uniform(0.0, 0.6) + 0.8 * out.turbidity;  // forward scattering blurs
  s.sensor.gamma = draw.uniform(2.0, 2.4);
  s.sensor.seed = static_cast<unsigned>(draw.bits() & 0x7fffffffU);
  // White balance: from none to most of the way to grey-world on the water's colour, with some error.
  const double strength = draw.uniform(0.0, 0.8);
  const Eigen::Vector3d& veil = s.water.veiling_light;
  Eigen::Vector3d gains;
  for (int c = 0; c < 3; ++c) gains[c] = std::pow(veil.mean() / std::max(veil[c], 1e-4), strength);
  gains /= gains.y();
  gains.x() *= draw.uniform(0.92, 1.08);
  gains.z() *= draw.uniform(0.92, 1.08);
  s.sensor.white_balance = gains.cwiseMax(0.5).cwiseMin(4.0);
}

}  // namespace

std::vector<std::string> SceneSamplerConfig::validate() const {
  std::vector<std::string> p;
  auto ordered = [&p](const std::string& name, double lo, double hi, double min, double max) {
    if (!(lo <= hi && lo >= min && hi <= max)) {
      p.push_back(name + " = [" + std::to_string(lo) + ", " + std::to_string(hi) + "] is not an interval within [" +
                  std::to_string(min) + ", " + std::to_string(max) + "]");
    }
  };
  ordered("width", width, width, 16, 8192);
  ordered("height", height, height, 16, 8192);
  if (width % 2 != 0 || height % 2 != 0) {  // a Bayer mosaic repeats every 2 x 2 pixels
    p.push_back("width and height must be even (the head renders a Bayer mosaic), got " + std::to_string(width) + "x" +
                std::to_string(height));
  }
  ordered("designated_objects", designated_objects.first, designated_objects.second, 1, 20);
  ordered("distractors", distractors.first, distractors.second, 0, 20);
  ordered("range_m", range_m.first, range_m.second, 0.3, 50);
  ordered("size_m", size_m.first, size_m.second, 0.02, 5);
  ordered("turbidity", turbidity.first, turbidity.second, 0, 1);
  ordered("water_type", water_type.first, water_type.second, 0, 2);
  ordered("target_luma", target_luma.first, target_luma.second, 1, 254);
  ordered("focal_length_mm", focal_length_mm.first, focal_length_mm.second, 1, 100);
  ordered("baseline_m", baseline_m.first, baseline_m.second, kMinBaselineM, kMaxBaselineM);
  ordered("occluder_probability", occluder_probability, occluder_probability, 0, 1);
  ordered("border_probability", border_probability, border_probability, 0, 1);
  if (designated.empty()) p.push_back("designated: no colour family");
  for (const auto* list : {&designated, &distractor_colours}) {
    for (const auto& name : *list) {
      const auto& all = colourFamilies();
      if (std::none_of(all.begin(), all.end(), [&](const ColourFamily& f) { return f.name == name; })) {
        p.push_back("colour family '" + name + "' is unknown");
      }
    }
  }
  for (const auto& name : designated) {
    if (std::find(distractor_colours.begin(), distractor_colours.end(), name) != distractor_colours.end()) {
      p.push_back("colour family '" + name + "' is both designated and a distractor");
    }
  }
  if (!distractor_colours.empty() || distractors.second == 0) return p;
  p.push_back("distractors: up to " + std::to_string(distractors.second) + " but no distractor colour");
  return p;
}

const std::vector<ColourFamily>& colourFamilies() {
  static const std::vector<ColourFamily> families{
      {"red", {-8.0, 10.0}, {0.65, 1.0}, {0.45, 0.95}},     // scarlet .. dull brick
      {"orange", {18.0, 35.0}, {0.7, 1.0}, {0.6, 1.0}},     // safety orange .. amber
      {"yellow", {45.0, 60.0}, {0.6, 1.0}, {0.7, 1.0}},     // golden .. lemon
      {"green", {85.0, 150.0}, {0.5, 1.0}, {0.35, 0.9}},    // lime .. bottle green
      {"white", {0.0, 360.0}, {0.0, 0.08}, {0.8, 0.97}},
      {"black", {0.0, 360.0}, {0.0, 0.3}, {0.04, 0.15}},
      {"grey", {0.0, 360.0}, {0.0, 0.08}, {0.3, 0.65}},
      {"blue", {200.0, 240.0}, {0.5, 1.0}, {0.3, 0.9}},
      {"purple", {265.0, 295.0}, {0.4, 0.9}, {0.3, 0.8}},
  };
  return families;
}

Eigen::Vector3d albedoFromHsv(double hue_deg, double saturation, double value) {
  const double h = std::fmod(std::fmod(hue_deg, 360.0) + 360.0, 360.0) / 60.0;
  const double c = value * saturation, x = c * (1.0 - std::abs(std::fmod(h, 2.0) - 1.0)), m = value - c;
  Eigen::Vector3d rgb;
  switch (static_cast<int>(h)) {
    case 0: rgb = {c, x, 0}; break;
    case 1: rgb = {x, c, 0}; break;
    case 2: rgb = {0, c, x}; break;
    case 3: rgb = {0, x, c}; break;
    case 4: rgb = {x, 0, c}; break;
    default: rgb = {c, 0, x}; break;
  }
  rgb.array() += m;
  // sRGB transfer curve to linear reflectance.
  for (int i = 0; i < 3; ++i) {
    rgb[i] = rgb[i] <= 0.04045 ? rgb[i] / 12.92 : std::pow((rgb[i] + 0.055) / 1.055, 2.4);
  }
  return rgb.cwiseMax(0.0).cwiseMin(1.0);
}

double boundingRadius(const SceneObject& o) {
  switch (o.shape) {
    case ShapeType::kSphere: return 0.5 * o.size_m.x();
    case ShapeType::kCylinder: return 0.5 * std::hypot(o.size_m.x(), o.size_m.z());
    case ShapeType::kBox: return 0.5 * o.size_m.norm();
    case ShapeType::kPanel: return 0.5 * std::hypot(o.size_m.x(), o.size_m.y());
  }
  return 0.0;
}

SampledScene sampleScene(std::uint64_t seed, const SceneSamplerConfig& config) {
  const std::vector<std::string> problems = config.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid scene sampler config", problems));
  Draw draw(seed);
  SampledScene out;
  out.seed = seed;
  Scene& s = out.scene;
  s.name = "random_" + std::to_string(seed);
  s.rig.pixel_size_um *= static_cast<double>(s.rig.width) / config.width;  // same field of view at any size
  s.rig.principal_offset_px *= static_cast<double>(config.width) / s.rig.width;
  s.rig.width = config.width;
  s.rig.height = config.height;
  Draw optics(seed ^ 0x6F70746963730000ULL);  // "optics": its own stream, so that fixed optics keep every scene
  s.rig.focal_length_mm = optics.uniform(config.focal_length_mm);
  s.rig.baseline_m = optics.uniform(config.baseline_m);
  drawWaterAndLight(draw, config, out);
  const StereoRig rig(s.rig);

  const int designated = draw.integer(config.designated_objects.first, config.designated_objects.second);
  const int distractors = draw.integer(config.distractors.first, config.distractors.second);
  const int occluder = draw.chance(config.occluder_probability) ? draw.integer(1, designated + distractors) : -1;
  for (int i = 0; i < designated + distractors; ++i) {
    const bool is_designated = i < designated;
    const auto& names = is_designated ? config.designated : config.distractor_colours;
    const ColourFamily& f = family(names[draw.integer(0, static_cast<int>(names.size()) - 1)]);
    for (int attempt = 0; attempt < 200; ++attempt) {
      SceneObject o = drawBody(draw, config);
      drawSurface(draw, f, o);
      const double radius = boundingRadius(o);
      if (i == occluder && !s.objects.empty()) {
        // In front of an object already placed, off its line of sight by up to its radius: hides part of it.
        const SceneObject& behind = s.objects[draw.integer(0, static_cast<int>(s.objects.size()) - 1)];
        const double far = behind.position_m.norm() - boundingRadius(behind) - radius - 0.05;
        const double near = std::max(config.range_m.first, radius + 0.25);
        if (far < near) continue;
        const Eigen::Vector3d side = behind.position_m.unitOrthogonal();
        const double turn = draw.uniform(-M_PI, M_PI);
        const Eigen::Vector3d offset = Eigen::AngleAxisd(turn, behind.position_m.normalized()) * side *
                                       draw.uniform(0.2, 1.0) * boundingRadius(behind);
        o.position_m = (behind.position_m + offset).normalized() * draw.uniform(near, far);
      } else {
        o.position_m = drawPosition(draw, config, rig, radius);
      }
      if (!fits(o, s.objects, s)) continue;
      o.name = o.colour + "_" + shapeName(o.shape) + "_" + std::to_string(i);
      s.objects.push_back(o);
      out.designated.push_back(is_designated);
      break;
    }
  }
  out.target_luma = draw.uniform(config.target_luma);
  autoExpose(s, out.target_luma);
  return out;
}

Scene downscaledScene(const Scene& scene, int factor) {
  if (factor < 1) throw std::invalid_argument("downscaledScene: factor must be >= 1");
  Scene small = scene;
  small.rig.width = std::max(16, scene.rig.width / factor);
  small.rig.height = std::max(16, scene.rig.height / factor);
  const double ratio = static_cast<double>(scene.rig.width) / small.rig.width;
  small.rig.pixel_size_um *= ratio;
  small.rig.principal_offset_px /= ratio;
  small.sensor.blur_sigma_px /= ratio;
  return small;
}

double meanLuma(const cv::Mat& bgr) {
  if (bgr.type() != CV_8UC3) throw std::invalid_argument("meanLuma: needs a CV_8UC3 BGR image");
  cv::Mat grey;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);  // BT.601 weights
  return cv::mean(grey)[0];
}

double autoExpose(Scene& scene, double target_luma, int probe_factor) {
  if (!(target_luma > 0.0 && target_luma < 255.0)) {
    throw std::invalid_argument("autoExpose: target luma " + std::to_string(target_luma) + " is outside (0, 255)");
  }
  Scene probe_scene = downscaledScene(scene, probe_factor);
  probe_scene.sensor.noise_sigma = 0.0;
  probe_scene.sensor.encoding = "bgr8";
  double luma = 0.0;
  for (int iteration = 0; iteration < 4; ++iteration) {
    probe_scene.light.exposure = scene.light.exposure;
    luma = meanLuma(Renderer(probe_scene).render(0.0, 0).left);
    if (std::abs(luma - target_luma) < 1.0) break;
    // Luma follows exposure^(1/gamma) until it clips: step in that power, damped near the ends of the scale.
    const double step = std::pow(std::max(target_luma, 1.0) / std::max(luma, 1.0), scene.sensor.gamma);
    scene.light.exposure = std::clamp(scene.light.exposure * std::clamp(step, 0.1, 10.0), 0.011, 99.0);
  }
  return luma;
}

}  // namespace sim
}  // namespace underwater_stereo
