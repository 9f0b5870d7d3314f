// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Randomised scenes (domain randomisation): a whole underwater scene drawn from one seed.
///
/// The sampler is a judge of the detector: it shares no colour, water or shape model with detection/. Its
/// colour families are described in the object's own (sRGB hue, saturation, value) terms; the water is a
/// physical absorption + scattering model; the camera auto-exposes on a low-resolution render of the scene.

#include <opencv2/core.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "underwater_stereo/sim/scene.h"

namespace underwater_stereo {
namespace sim {

/// The ranges scenes are drawn from. Defaults are the documented distribution; each pair is [min, max].
struct SceneSamplerConfig {
  int width = 1920;                               ///< [px] image size of the sampled rig (field of view kept)
  int height = 1200;                              ///< [px]
  std::pair<int, int> designated_objects{1, 4};   ///< objects of a designated colour per scene
  std::pair<int, int> distractors{0, 3};          ///< objects of other colours per scene
  std::pair<double, double> range_m{0.5, 5.0};    ///< [m] camera to object centre (uniform)
  std::pair<double, double> size_m{0.1, 0.6};     ///< [m] an object's largest extent (uniform)
  std::pair<double, double> turbidity{0.0, 1.0};  ///< 0: clear, 1: murky (scattering 0.02 .. 0.25 /m)
  std::pair<double, double> water_type{0.0, 2.0}; ///< 0: clear blue ocean, 1: green coastal, 2: brown (CDOM)
  std::pair<double, double> target_luma{30.0, 200.0};  ///< auto-exposure's target mean BT.601 luma of the left image
  /// [mm] lens focal length in air (uniform; the sensor keeps its size, so a shorter lens sees wider). Drawn, with
  /// the baseline, from a generator of its own: the other draws of a seed do not depend on these two ranges.
  std::pair<double, double> focal_length_mm{RigConfig{}.focal_length_mm, RigConfig{}.focal_length_mm};
  std::pair<double, double> baseline_m{RigConfig{}.baseline_m, RigConfig{}.baseline_m};  ///< [m] between the cameras
  double occluder_probability = 0.35;             ///< chance per scene that one object is placed to hide part of another
  double border_probability = 0.25;               ///< chance per object that its centre may lie at or beyond the border
  /// Designated colour families, named as the detector config names them.
  std::vector<std::string> designated{"red", "orange", "yellow", "green"};
  /// Distractor colour families (never designated).
  std::vector<std::string> distractor_colours{"white", "black", "grey", "blue", "purple"};

  /// Whether scenes differ in their optics (focal length or baseline), so that each needs its own head.
  bool variesOptics() const {
    return focal_length_mm.first != focal_length_mm.second || baseline_m.first != baseline_m.second;
  }

  /// Every problem with the ranges (min > max, a colour family the sampler does not know...). Empty when valid.
  std::vector<std::string> validate() const;
};

/// One sampled scene and the parameters it was drawn from (for binning the evaluation).
struct SampledScene {
  Scene scene;
  std::uint64_t seed = 0;
  double turbidity = 0.0;     ///< 0..1, see SceneSamplerConfig::turbidity
  double water_type = 0.0;    ///< 0..2, see SceneSamplerConfig::water_type
  double target_luma = 0.0;   ///< the auto-exposure's target
  std::vector<bool> designated;  ///< per scene object: of a designated colour family (else a distractor)
};

/// Colour family of a sampled albedo: sRGB hue [deg], saturation and value ranges (the object's own colour).
struct ColourFamily {
  std::string name;
  std::pair<double, double> hue_deg;     ///< may start below 0 (reds wrap around)
  std::pair<double, double> saturation;
  std::pair<double, double> value;
};

/// The colour families the sampler knows: red (scarlet .. dull brick), orange, yellow, green, and the
/// distractors white, black, grey, blue, purple.
const std::vector<ColourFamily>& colourFamilies();

/// Linear-RGB albedo of an sRGB colour given as hue [deg], saturation and value (0..1).
Eigen::Vector3d albedoFromHsv(double hue_deg, double saturation, double value);

/// [m] Radius of the smallest sphere about the object's centre that holds all of it (sampled objects keep
/// these spheres apart, so they never intersect).
double boundingRadius(const SceneObject& object);

/// Draws the scene of `seed`: the same seed and config always give the same scene.
/// @throw std::invalid_argument when `config` does not validate.
SampledScene sampleScene(std::uint64_t seed, const SceneSamplerConfig& config = {});

/// A copy of `scene` rendered `factor` times smaller with the same field of view (for quick probes).
Scene downscaledScene(const Scene& scene, int factor);

/// Mean BT.601 luma (0-255) of a BGR8 image.
double meanLuma(const cv::Mat& bgr);

/// Sets scene.light.exposure so that the left image's mean BT.601 luma (without noise) is about
/// `target_luma`, from renders `probe_factor` times smaller. Returns the luma reached by the probe.
/// @throw std::invalid_argument when the target is outside (0, 255) or the scene is invalid.
double autoExpose(Scene& scene, double target_luma, int probe_factor = 8);

}  // namespace sim
}  // namespace underwater_stereo
