// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A simulated underwater scene: stereo head, water, light, seabed and objects, as a YAML file describes it.
///
/// World frame: the left camera's optical frame at time 0 (x right, y down, z forward). The seabed is
/// the plane y = seabed.depth_m below the camera. Every pose in a scene file is in this frame.

#include <Eigen/Core>

#include <string>
#include <vector>

namespace YAML {
class Node;
}

namespace underwater_stereo {
namespace sim {

/// The stereo head: two identical pinhole cameras behind a flat port, with lens distortion and a
/// small rotation between them (never a perfectly rectified pair).
struct RigConfig {
  int width = 1920;                 ///< [px] Basler acA1920-50gc
  int height = 1200;                ///< [px]
  double pixel_size_um = 5.86;      ///< [um] sensor pixel pitch
  double focal_length_mm = 8.0;     ///< [mm] lens focal length in air
  double water_focal_factor = 1.333;  ///< refraction at the flat port scales the focal length by about n_water
  double baseline_m = 0.12;         ///< [m] distance between the optical centres
  Eigen::Vector3d right_rotation_deg{0.3, -0.4, 0.2};  ///< [deg] right camera's rotation (x, y, z) relative to the left
  Eigen::Vector3d right_offset_m{0.0, 0.002, 0.001};   ///< [m] right centre's deviation from (baseline, 0, 0)
  std::vector<double> left_distortion{-0.08, 0.05, 0.0005, -0.0003, 0.0};   ///< plumb_bob k1 k2 p1 p2 k3
  std::vector<double> right_distortion{-0.075, 0.045, -0.0004, 0.0002, 0.0};
  double principal_offset_px = 6.0;  ///< [px] principal points sit this far (x and y, opposite signs) off centre

  /// [px] focal length in water.
  double focalPx() const { return focal_length_mm * 1e-3 / (pixel_size_um * 1e-6) * water_focal_factor; }
};

/// Light in the water column. Colours are linear RGB in 0..1 (before the camera's gamma).
struct WaterConfig {
  Eigen::Vector3d attenuation_per_m{0.45, 0.09, 0.06};  ///< [1/m] r, g, b beam attenuation (red is lost fastest)
  Eigen::Vector3d veiling_light{0.05, 0.28, 0.32};      ///< backscatter radiance far away (the water's own colour)
  double veiling_gradient = 0.6;                        ///< how much brighter the water is looking up than level
};

struct LightConfig {
  Eigen::Vector3d downwelling{0.55, 0.85, 0.9};  ///< irradiance from the surface on a surface facing the sun
  double ambient = 0.35;                         ///< fraction of downwelling light reaching faces turned away
  /// Direction the sunlight travels in the world frame (y down): (0, 1, 0) straight down. Normalised on use.
  Eigen::Vector3d sun_direction{0.0, 1.0, 0.0};
  /// 0..1: how strongly the wavy surface focuses sunlight into a moving web of caustics on surfaces
  /// facing the sun (0: none; 1: between dark gaps and bright lines, mean unchanged).
  double caustics = 0.0;
  double caustics_scale_m = 0.25;                ///< [m] size of a caustic cell on a surface
  double lamp_intensity = 0.6;                   ///< vehicle lamp at the head, irradiance at 1 m (falls off as 1/d^2)
  Eigen::Vector3d lamp_colour{1.0, 1.0, 1.0};    ///< relative r, g, b of the lamp
  double exposure = 1.0;                         ///< global gain: from very dark (0.1) to washed out (4)
};

struct SeabedConfig {
  bool enabled = true;
  double depth_m = 2.0;                      ///< [m] seabed plane below the camera (world y)
  Eigen::Vector3d albedo{0.55, 0.5, 0.4};    ///< sand colour
  double texture = 0.5;                      ///< 0..1 relative albedo variation
  double texture_scale_m = 0.15;             ///< [m] size of the texture's features
};

struct SensorConfig {
  std::string encoding = "bayer_rggb8";  ///< bayer_rggb8 (as the real cameras give) or bgr8
  double noise_sigma = 2.0;              ///< [DN] Gaussian read noise on the 8-bit image
  double blur_sigma_px = 0.0;            ///< [px] optical blur (0: none)
  double gamma = 2.2;                    ///< encoding gamma applied to linear radiance
  Eigen::Vector3d white_balance{1.0, 1.0, 1.0};  ///< r, g, b gains on linear radiance before gamma (camera white balance)
  unsigned seed = 1;                     ///< noise seed (a frame's noise also depends on its index)
};

/// Constant-velocity motion plus a vertical bob, for a sequence that is not one frame repeated.
struct Motion {
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  ///< [m/s] in the world frame
  double yaw_rate_dps = 0.0;          ///< [deg/s] rotation about the world y axis (down)
  double bob_amplitude_m = 0.0;       ///< [m] vertical oscillation
  double bob_period_s = 4.0;          ///< [s]
};

enum class ShapeType { kSphere, kCylinder, kBox, kPanel };

/// Name of a shape as it appears in scene files and messages ("sphere", "cylinder", "box", "plane").
std::string shapeName(ShapeType shape);

struct SceneObject {
  std::string name;
  ShapeType shape = ShapeType::kSphere;
  std::string colour;                                      ///< designated colour class, e.g. "red"
  Eigen::Vector3d albedo{0.8, 0.1, 0.1};                   ///< linear RGB reflectance 0..1
  double texture = 0.15;                                   ///< 0..1 relative albedo variation (dirt, print)
  double specular = 0.0;                                   ///< 0..1 white specular reflectance (gloss paint)
  double shininess = 40.0;                                 ///< Blinn-Phong exponent: 5 (satin) .. 500 (mirror-like)
  Eigen::Vector3d position_m = Eigen::Vector3d(0, 0, 2);   ///< [m] centre at time 0, world frame
  Eigen::Vector3d rpy_deg = Eigen::Vector3d::Zero();       ///< [deg] orientation (roll x, pitch y, yaw z)
  /// [m] sphere: (d, d, d); cylinder: (d, d, length along the local z axis); box: edges along local x, y, z;
  /// panel: (width along x, height along y, 0), normal along local z.
  Eigen::Vector3d size_m = Eigen::Vector3d(0.25, 0.25, 0.25);
  Motion motion;
};

struct Scene {
  std::string name;
  RigConfig rig;
  WaterConfig water;
  LightConfig light;
  SeabedConfig seabed;
  SensorConfig sensor;
  Motion camera_motion;
  std::vector<SceneObject> objects;

  /// Every problem with the scene; empty when it can be rendered.
  std::vector<std::string> validate() const;
};

/// Parses a scene from YAML. @throw std::invalid_argument listing every problem (unknown keys, wrong
/// types, invalid values).
Scene parseScene(const YAML::Node& root);
/// Loads and parses a scene file. @throw std::invalid_argument when unreadable or invalid.
Scene loadSceneFile(const std::string& path);

}  // namespace sim
}  // namespace underwater_stereo
