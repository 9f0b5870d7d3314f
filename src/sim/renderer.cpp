// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/sim/renderer.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/sim/primitive.h"
#include "underwater_stereo/sim/value_noise.h"

namespace underwater_stereo {
namespace sim {
namespace {

constexpr float kObjectTextureFrequency = 14.0F;  // [1/m] ~7 cm blotches on object surfaces

/// Unit viewing ray of every pixel of a distorted camera, in its optical frame, into `rays` (CV_32FC3, cam's size).
void pixelRays(const PinholeCamera& cam, cv::Mat rays) {
  cv::Mat pixels(cam.width * cam.height, 1, CV_64FC2);
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) pixels.at<cv::Vec2d>(v * cam.width + u) = cv::Vec2d(u, v);
  }
  cv::Mat normalised;
  cv::undistortPoints(pixels, normalised, cv::Mat(cam.K), cv::Mat(cam.D), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      const cv::Vec2d xy = normalised.at<cv::Vec2d>(v * cam.width + u);
      const double norm = std::sqrt(xy[0] * xy[0] + xy[1] * xy[1] + 1.0);
      rays.at<cv::Vec3f>(v, u) = cv::Vec3f(static_cast<float>(xy[0] / norm), static_cast<float>(xy[1] / norm),
                                           static_cast<float>(1.0 / norm));
    }
  }
}

Eigen::Vector3d displacement(const Motion& m, double t) {
  Eigen::Vector3d d = m.velocity_mps * t;
  d.y() += m.bob_amplitude_m * std::sin(2.0 * M_PI * t / m.bob_period_s);
  return d;
}

/// Pose of the left optical frame in the world at time t.
Eigen::Isometry3d cameraPose(const Motion& m, double t) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const double yaw_deg = m.yaw_rate_dps * t + m.yaw_amplitude_deg * (1.0 - std::cos(2.0 * M_PI * t / m.yaw_period_s)) / 2;
  pose.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pose.translation() = displacement(m, t);
  return pose;
}

struct PlacedObject {
  Primitive primitive;
  Eigen::Vector3f albedo;
  float texture;
  float specular;
  float shininess;
  std::uint32_t seed;
};

/// Everything the per-pixel shader needs, in float, for one camera at one instant.
struct ShadingContext {
  const std::vector<PlacedObject>* objects;
  const Scene* scene;
  Eigen::Matrix3f cam_rotation;     // camera -> world
  Eigen::Vector3f cam_position;     // world
  Eigen::Vector3f attenuation;      // r, g, b
  Eigen::Vector3f veiling;
  Eigen::Vector3f downwelling;
  Eigen::Vector3f sun_direction;    // unit, the way the light travels
  Eigen::Vector3f lamp_colour;
  float exposure;
  float time_s;                     // moves the caustics
};

constexpr std::uint32_t kCausticsSeed = 7919U;

/// Relative sunlight (mean ~1) at world point p: a web of bright lines where the wavy surface focuses light.
/// The pattern lives on the horizontal plane through the camera, carried along the sun's direction, so a
/// surface sees the cell the sunlight that reaches it crossed there; it drifts with time.
float causticFactor(const ShadingContext& ctx, const Eigen::Vector3f& p) {
  const LightConfig& light = ctx.scene->light;
  if (light.caustics <= 0.0) return 1.0F;
  const Eigen::Vector3f& s = ctx.sun_direction;
  const float k = 1.0F / static_cast<float>(light.caustics_scale_m);
  const float x = (p.x() - s.x() / s.y() * p.y()) * k + 0.3F * ctx.time_s;
  const float z = (p.z() - s.z() / s.y() * p.y()) * k + 0.2F * ctx.time_s;
  float web = 0.0F;
  for (int octave = 0; octave < 2; ++octave) {
    const float f = octave == 0 ? 1.0F : 2.3F;
    // Ridges of value noise: thin bright lines where the noise crosses its middle.
    const float ridge = 1.0F - std::abs(2.0F * valueNoise(f * x, 0.5F * ctx.time_s, f * z, kCausticsSeed + octave) - 1.0F);
    const float r2 = ridge * ridge, r4 = r2 * r2;
    web += (octave == 0 ? 0.65F : 0.35F) * r4 * r2;
  }
  // ridge^6 averages about 1/7 for uniform noise: 7 * web has mean ~1.
  return std::max(0.0F, 1.0F + static_cast<float>(light.caustics) * (7.0F * web - 1.0F));
}

/// Linear RGB radiance reaching the camera along a world ray; label = 1 + object index, 0 otherwise.
Eigen::Vector3f shade(const ShadingContext& ctx, const Eigen::Vector3f& dir, std::uint16_t& label) {
  const Scene& s = *ctx.scene;
  const Eigen::Vector3f& o = ctx.cam_position;
  float t_best = 1e6F;
  int best = -1;
  Hit hit, candidate;
  for (std::size_t i = 0; i < ctx.objects->size(); ++i) {
    if ((*ctx.objects)[i].primitive.intersect(o, dir, t_best, candidate)) {
      t_best = candidate.t;
      hit = candidate;
      best = static_cast<int>(i);
    }
  }
  Eigen::Vector3f albedo;
  Eigen::Vector3f normal;
  bool surface = best >= 0;
  if (surface) {
    const PlacedObject& obj = (*ctx.objects)[best];
    const Eigen::Vector3f p = hit.local * kObjectTextureFrequency;
    const float tex = textureNoise(p.x(), p.y(), p.z(), obj.seed);
    albedo = obj.albedo * (1.0F + obj.texture * (2.0F * tex - 1.0F));
    normal = hit.normal;
    label = static_cast<std::uint16_t>(best + 1);
  } else {
    label = 0;
    if (s.seabed.enabled && dir.y() > 1e-6F) {
      const float t = (static_cast<float>(s.seabed.depth_m) - o.y()) / dir.y();
      if (t > 0.0F && t < t_best) {
        const Eigen::Vector3f p = o + t * dir;
        const float k = 1.0F / static_cast<float>(s.seabed.texture_scale_m);
        const float tex = textureNoise(p.x() * k, 0.0F, p.z() * k, s.sensor.seed + 101U);
        albedo = s.seabed.albedo.cast<float>() * (1.0F + static_cast<float>(s.seabed.texture) * (2.0F * tex - 1.0F));
        normal = Eigen::Vector3f(0.0F, -1.0F, 0.0F);
        t_best = t;
        surface = true;
      }
    }
  }
  // Veiling light: brighter looking up (world y points down).
  const Eigen::Vector3f veiling =
      ctx.veiling * std::max(0.2F, 1.0F + static_cast<float>(s.water.veiling_gradient) * (-dir.y()));
  if (!surface) return veiling * ctx.exposure;

  const float up = std::max(0.0F, -normal.dot(ctx.sun_direction));
  const float ambient = static_cast<float>(s.light.ambient);
  const Eigen::Vector3f transmit = (-ctx.attenuation * t_best).array().exp().matrix();
  const float facing = std::max(0.0F, -normal.dot(dir));
  const float d = std::max(t_best, 0.2F);
  const float lamp = static_cast<float>(s.light.lamp_intensity) * facing / (d * d);
  const float sun = up > 0.0F ? up * causticFactor(ctx, o + t_best * dir) : 0.0F;
  const Eigen::Vector3f lamp_irradiance = (lamp * ctx.lamp_colour).cwiseProduct(transmit);
  const Eigen::Vector3f irradiance = ctx.downwelling * (ambient + (1.0F - ambient) * sun) + lamp_irradiance;
  Eigen::Vector3f direct = albedo.cwiseProduct(irradiance).cwiseProduct(transmit);
  if (best >= 0 && (*ctx.objects)[best].specular > 0.0F) {
    // Blinn-Phong highlights of the lamp (at the camera: half vector = -dir) and of the sun.
    const PlacedObject& obj = (*ctx.objects)[best];
    const Eigen::Vector3f half_sun = (-dir - ctx.sun_direction).normalized();
    const float lamp_lobe = std::pow(facing, obj.shininess);
    const float sun_lobe = up > 0.0F ? std::pow(std::max(0.0F, normal.dot(half_sun)), obj.shininess) : 0.0F;
    const Eigen::Vector3f glint = lamp_lobe * lamp_irradiance / std::max(facing, 1e-3F) + sun_lobe * ctx.downwelling;
    direct += obj.specular * glint.cwiseProduct(transmit);
  }
  const Eigen::Vector3f backscatter = veiling.cwiseProduct(Eigen::Vector3f::Ones() - transmit);
  return (direct + backscatter) * ctx.exposure;
}

/// Renders one camera into linear-light BGR float and (optionally) the label image.
void renderCamera(const ShadingContext& ctx, const cv::Mat& rays, cv::Mat& linear_bgr, cv::Mat* labels) {
  linear_bgr.create(rays.size(), CV_32FC3);
  if (labels) labels->create(rays.size(), CV_16UC1);
  cv::parallel_for_(cv::Range(0, rays.rows), [&](const cv::Range& range) {
    for (int v = range.start; v < range.end; ++v) {
      const auto* ray = rays.ptr<cv::Vec3f>(v);
      auto* out = linear_bgr.ptr<cv::Vec3f>(v);
      std::uint16_t* lab = labels ? labels->ptr<std::uint16_t>(v) : nullptr;
      for (int u = 0; u < rays.cols; ++u) {
        const Eigen::Vector3f dir = ctx.cam_rotation * Eigen::Vector3f(ray[u][0], ray[u][1], ray[u][2]);
        std::uint16_t label = 0;
        const Eigen::Vector3f rgb = shade(ctx, dir, label);
        out[u] = cv::Vec3f(rgb.z(), rgb.y(), rgb.x());
        if (lab) lab[u] = label;
      }
    }
  });
}

/// The image-sized float images one render works in (each camera's linear light, then develop()'s steps), carved
/// out of ONE allocation: above glibc's mmap threshold (the launch files set 32 MB; 138 MB at 1920x1200) it is
/// mapped for the render and unmapped after, where five 27.6 MB images allocated one by one would come from the
/// heap and, freed, stay there (the launch files' MALLOC_TRIM_THRESHOLD_), moving RSS by where they fell.
/// The images share the buffer's reference count; none of them is returned.
class Scratch {
 public:
  enum Slot { kLeftLinear, kRightLinear, kEncoded, kBlurred, kNoise, kSlots };
  explicit Scratch(cv::Size size) : buffer_(kSlots * size.height, size.width, CV_32FC3), rows_(size.height) {}
  cv::Mat operator[](Slot slot) const { return buffer_.rowRange(slot * rows_, (slot + 1) * rows_); }

 private:
  cv::Mat buffer_;
  int rows_;
};

/// Camera response: gamma, blur, read noise, 8-bit quantisation, Bayer mosaic; linear_bgr is overwritten.
cv::Mat develop(cv::Mat linear_bgr, const SensorConfig& sensor, std::uint64_t noise_seed, const Scratch& scratch) {
  cv::Mat encoded = scratch[Scratch::kEncoded];
  cv::max(linear_bgr, 0.0, encoded);
  if (sensor.white_balance != Eigen::Vector3d::Ones()) {
    cv::multiply(encoded, cv::Scalar(sensor.white_balance.z(), sensor.white_balance.y(), sensor.white_balance.x()),
                 encoded);
  }
  cv::min(encoded, 1.0, encoded);
  cv::pow(encoded, 1.0 / sensor.gamma, encoded);
  encoded *= 255.0;
  if (sensor.blur_sigma_px > 0.0) {
    cv::Mat blurred = scratch[Scratch::kBlurred];
    // Isolated: encoded is a slot of the scratch buffer, and OpenCV would take its border rows from the slots
    // beside it.
    cv::GaussianBlur(encoded, blurred, cv::Size(), sensor.blur_sigma_px, 0, cv::BORDER_DEFAULT | cv::BORDER_ISOLATED);
    encoded = blurred;
  }
  if (sensor.noise_sigma > 0.0) {
    cv::Mat noise = scratch[Scratch::kNoise];
    cv::RNG rng(noise_seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, sensor.noise_sigma);
    encoded += noise;
  }
  // 8-bit, in the linear image's bytes (no longer needed): a view, so mosaiced or copied before it is returned.
  cv::Mat bgr8(encoded.size(), CV_8UC3, linear_bgr.data);
  encoded.convertTo(bgr8, CV_8UC3);
  return sensor.encoding == "bayer_rggb8" ? mosaicRggb(bgr8) : bgr8.clone();
}

/// Every object of `scene` that holds one of `rig`'s cameras at `time_s`, as "objects[i] (name): the left camera lies
/// inside it" (Renderer::camerasInside).
std::vector<std::string> objectsHoldingCameras(const Scene& scene, const StereoRig& rig, double time_s) {
  std::vector<std::string> held;
  const Eigen::Isometry3d left = cameraPose(scene.camera_motion, time_s);
  const std::pair<const char*, Eigen::Vector3d> cameras[] = {{"left", left.translation()},
                                                             {"right", (left * rig.rightInLeft()).translation()}};
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const SceneObject& o = scene.objects[i];
    const Primitive placed(o.shape, (o.position_m + displacement(o.motion, time_s)).cast<float>(),
                           rotationFromRpyDeg(o.rpy_deg).cast<float>(), o.size_m.cast<float>());
    for (const auto& [camera, at] : cameras) {
      if (placed.contains(at.cast<float>())) {
        held.push_back("objects[" + std::to_string(i) + "] (" + o.name + "): the " + camera + " camera lies inside it");
      }
    }
  }
  return held;
}

/// `held` (objectsHoldingCameras) at time `time_s`.
std::vector<std::string> atTime(std::vector<std::string> held, double time_s) {
  std::ostringstream time;
  time << time_s;
  for (std::string& h : held) h += " at time " + time.str() + " s";
  return held;
}

/// @throw std::invalid_argument listing every problem of `scene` (Scene::validate) and every object that holds a
/// camera at time 0 (its view would be the object's inside, no picture of the scene).
void requireRenderable(const Scene& scene, const StereoRig& rig) {
  std::vector<std::string> problems = scene.validate();
  if (problems.empty()) problems = atTime(objectsHoldingCameras(scene, rig, 0.0), 0.0);
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid scene", problems));
}

}  // namespace

cv::Mat mosaicRggb(const cv::Mat& bgr) {
  if (bgr.type() != CV_8UC3) throw std::invalid_argument("mosaicRggb: needs CV_8UC3 BGR");
  cv::Mat bayer(bgr.size(), CV_8UC1);
  for (int v = 0; v < bgr.rows; ++v) {
    const auto* in = bgr.ptr<cv::Vec3b>(v);
    auto* out = bayer.ptr<std::uint8_t>(v);
    for (int u = 0; u < bgr.cols; ++u) {
      // RGGB: even rows R G R G..., odd rows G B G B...; BGR channel index 2 = R, 1 = G, 0 = B.
      const int channel = (v % 2 == 0) ? (u % 2 == 0 ? 2 : 1) : (u % 2 == 0 ? 1 : 0);
      out[u] = in[u][channel];
    }
  }
  return bayer;
}

Renderer::Renderer(Scene scene) : scene_(std::move(scene)), rig_(scene_.rig) {
  requireRenderable(scene_, rig_);
  // Both cameras' rays in one allocation (55 MB at 1920x1200), unmapped when the renderer goes, as Scratch's.
  const cv::Mat rays(2 * rig_.left().height, rig_.left().width, CV_32FC3);
  left_rays_ = rays.rowRange(0, rig_.left().height);
  right_rays_ = rays.rowRange(rig_.left().height, rays.rows);
  pixelRays(rig_.left(), left_rays_);
  pixelRays(rig_.right(), right_rays_);
}

Renderer::Renderer(Scene scene, const Renderer& rays_from) : scene_(std::move(scene)), rig_(scene_.rig) {
  requireRenderable(scene_, rig_);
  const RigConfig &a = scene_.rig, &b = rays_from.scene_.rig;
  if (a.width != b.width || a.height != b.height || a.pixel_size_um != b.pixel_size_um ||
      a.focal_length_mm != b.focal_length_mm || a.water_focal_factor != b.water_focal_factor ||
      a.baseline_m != b.baseline_m || a.right_rotation_deg != b.right_rotation_deg ||
      a.right_offset_m != b.right_offset_m || a.left_distortion != b.left_distortion ||
      a.right_distortion != b.right_distortion || a.principal_offset_px != b.principal_offset_px) {
    throw std::invalid_argument("Renderer::withScene: scene '" + scene_.name + "' has another rig");
  }
  left_rays_ = rays_from.left_rays_;
  right_rays_ = rays_from.right_rays_;
}

Renderer Renderer::withScene(Scene scene) const { return Renderer(std::move(scene), *this); }

std::vector<std::string> Renderer::camerasInside(double time_s) const {
  return atTime(objectsHoldingCameras(scene_, rig_, time_s), time_s);
}

std::vector<std::string> Renderer::camerasInside(int frames, double rate_hz) const {
  if (frames < 0 || !(rate_hz > 0) || !std::isfinite(rate_hz)) {
    throw std::invalid_argument("Renderer::camerasInside: frames must be >= 0 and the rate a positive number");
  }
  std::vector<std::pair<std::string, std::vector<int>>> held;  // in the order first met: what, at which frames
  for (int k = 0; k < frames; ++k) {
    for (const std::string& h : objectsHoldingCameras(scene_, rig_, k / rate_hz)) {
      auto same = std::find_if(held.begin(), held.end(), [&](const auto& e) { return e.first == h; });
      if (same == held.end()) same = held.insert(held.end(), {h, {}});
      same->second.push_back(k);
    }
  }
  std::vector<std::string> out;
  for (const auto& [what, at] : held) {
    constexpr int kRangesShown = 10;  // a bobbing object may meet the camera every few frames of a long run
    std::string ranges;  // consecutive frames as one range: "frames 3-40, 52"
    int count = 0;
    for (std::size_t a = 0, b = 0; a < at.size(); a = b, ++count) {
      for (b = a + 1; b < at.size() && at[b] == at[b - 1] + 1; ++b) {
      }
      if (count < kRangesShown) {
        ranges += (ranges.empty() ? "" : ", ") + std::to_string(at[a]) + (b - a > 1 ? "-" + std::to_string(at[b - 1]) : "");
      }
    }
    const std::string more = count > kRangesShown ? " and " + std::to_string(count - kRangesShown) + " more ranges (" +
                                                        std::to_string(at.size()) + " of "
                                                  : " (of ";
    std::ostringstream rate;
    rate << rate_hz;
    out.push_back(what + " at frame" + (at.size() > 1 ? "s " : " ") + ranges + more + std::to_string(frames) + " at " +
                  rate.str() + " Hz)");
  }
  return out;
}

RenderedPair Renderer::render(double time_s, std::uint64_t frame_index) const {
  if (const std::vector<std::string> inside = camerasInside(time_s); !inside.empty()) {
    throw std::invalid_argument(joinProblems("scene '" + scene_.name + "' cannot be rendered", inside));
  }
  const Eigen::Isometry3d left_pose = cameraPose(scene_.camera_motion, time_s);
  const Eigen::Isometry3d right_pose = left_pose * rig_.rightInLeft();

  std::vector<PlacedObject> placed;
  RenderedPair out;
  out.time_s = time_s;
  out.camera_pose = left_pose;
  out.encoding = scene_.sensor.encoding;
  for (std::size_t i = 0; i < scene_.objects.size(); ++i) {
    const SceneObject& o = scene_.objects[i];
    const Eigen::Vector3d centre = o.position_m + displacement(o.motion, time_s);
    const Eigen::Matrix3d rotation = rotationFromRpyDeg(o.rpy_deg);
    placed.push_back({Primitive(o.shape, centre.cast<float>(), rotation.cast<float>(), o.size_m.cast<float>()),
                      o.albedo.cast<float>(), static_cast<float>(o.texture), static_cast<float>(o.specular),
                      static_cast<float>(o.shininess), static_cast<std::uint32_t>(1000 + i)});
    GroundTruthObject gt;
    gt.name = o.name;
    gt.shape = shapeName(o.shape);
    gt.colour = o.colour;
    gt.albedo = o.albedo;
    gt.size_m = o.size_m;
    gt.centre_world_m = centre;
    gt.centre_left_m = left_pose.inverse() * centre;
    gt.orientation_left = Eigen::Quaterniond(left_pose.linear().transpose() * rotation);
    gt.range_m = gt.centre_left_m.norm();
    out.ground_truth.push_back(gt);
  }

  ShadingContext ctx{&placed,
                     &scene_,
                     left_pose.linear().cast<float>(),
                     left_pose.translation().cast<float>(),
                     scene_.water.attenuation_per_m.cast<float>(),
                     scene_.water.veiling_light.cast<float>(),
                     scene_.light.downwelling.cast<float>(),
                     scene_.light.sun_direction.normalized().cast<float>(),
                     scene_.light.lamp_colour.cast<float>(),
                     static_cast<float>(scene_.light.exposure),
                     static_cast<float>(time_s)};
  const Scratch scratch(left_rays_.size());
  cv::Mat left_linear = scratch[Scratch::kLeftLinear], right_linear = scratch[Scratch::kRightLinear];
  renderCamera(ctx, left_rays_, left_linear, &out.left_labels);
  ctx.cam_rotation = right_pose.linear().cast<float>();
  ctx.cam_position = right_pose.translation().cast<float>();
  renderCamera(ctx, right_rays_, right_linear, nullptr);

  const std::uint64_t seed = scene_.sensor.seed * 1000003ULL + frame_index * 2ULL;
  out.left = develop(left_linear, scene_.sensor, seed, scratch);
  out.right = develop(right_linear, scene_.sensor, seed + 1, scratch);

  for (std::size_t i = 0; i < out.ground_truth.size(); ++i) {
    const cv::Mat mask = out.left_labels == static_cast<std::uint16_t>(i + 1);
    out.ground_truth[i].visible_pixels = cv::countNonZero(mask);
    if (out.ground_truth[i].visible_pixels > 0) out.ground_truth[i].roi_left = cv::boundingRect(mask);
  }
  return out;
}

}  // namespace sim
}  // namespace underwater_stereo
