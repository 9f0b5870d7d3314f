// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/sim/renderer.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/sim/primitive.h"
#include "underwater_stereo/sim/value_noise.h"

namespace underwater_stereo {
namespace sim {
namespace {

constexpr float kObjectTextureFrequency = 14.0F;  // [1/m] ~7 cm blotches on object surfaces

/// Unit viewing ray of every pixel of a distorted camera, in its optical frame.
cv::Mat pixelRays(const PinholeCamera& cam) {
  cv::Mat pixels(cam.width * cam.height, 1, CV_64FC2);
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) pixels.at<cv::Vec2d>(v * cam.width + u) = cv::Vec2d(u, v);
  }
  cv::Mat normalised;
  cv::undistortPoints(pixels, normalised, cv::Mat(cam.K), cv::Mat(cam.D), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 50, 1e-12));
  cv::Mat rays(cam.height, cam.width, CV_32FC3);
  for (int v = 0; v < cam.height; ++v) {
    for (int u = 0; u < cam.width; ++u) {
      const cv::Vec2d xy = normalised.at<cv::Vec2d>(v * cam.width + u);
      const double norm = std::sqrt(xy[0] * xy[0] + xy[1] * xy[1] + 1.0);
      rays.at<cv::Vec3f>(v, u) = cv::Vec3f(static_cast<float>(xy[0] / norm), static_cast<float>(xy[1] / norm),
                                           static_cast<float>(1.0 / norm));
    }
  }
  return rays;
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
  float exposure;
};

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

  const float up = std::max(0.0F, -normal.y());
  const float ambient = static_cast<float>(s.light.ambient);
  const Eigen::Vector3f transmit = (-ctx.attenuation * t_best).array().exp().matrix();
  const float facing = std::max(0.0F, -normal.dot(dir));
  const float d = std::max(t_best, 0.2F);
  const float lamp = static_cast<float>(s.light.lamp_intensity) * facing / (d * d);
  const Eigen::Vector3f irradiance = ctx.downwelling * (ambient + (1.0F - ambient) * up) + Eigen::Vector3f::Constant(lamp).cwiseProduct(transmit);
  const Eigen::Vector3f direct = albedo.cwiseProduct(irradiance).cwiseProduct(transmit);
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

/// Camera response: gamma, blur, read noise, 8-bit quantisation, Bayer mosaic.
cv::Mat develop(const cv::Mat& linear_bgr, const SensorConfig& sensor, std::uint64_t noise_seed) {
  cv::Mat encoded;
  cv::max(linear_bgr, 0.0, encoded);
  cv::min(encoded, 1.0, encoded);
  cv::pow(encoded, 1.0 / sensor.gamma, encoded);
  encoded *= 255.0;
  if (sensor.blur_sigma_px > 0.0) cv::GaussianBlur(encoded, encoded, cv::Size(), sensor.blur_sigma_px);
  if (sensor.noise_sigma > 0.0) {
    cv::Mat noise(encoded.size(), encoded.type());
    cv::RNG rng(noise_seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, sensor.noise_sigma);
    encoded += noise;
  }
  cv::Mat bgr8;
  encoded.convertTo(bgr8, CV_8UC3);
  return sensor.encoding == "bayer_rggb8" ? mosaicRggb(bgr8) : bgr8;
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
  const std::vector<std::string> problems = scene_.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid scene", problems));
  left_rays_ = pixelRays(rig_.left());
  right_rays_ = pixelRays(rig_.right());
}

RenderedPair Renderer::render(double time_s, std::uint64_t frame_index) const {
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
                      o.albedo.cast<float>(), static_cast<float>(o.texture), static_cast<std::uint32_t>(1000 + i)});
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
                     static_cast<float>(scene_.light.exposure)};
  cv::Mat left_linear, right_linear;
  renderCamera(ctx, left_rays_, left_linear, &out.left_labels);
  ctx.cam_rotation = right_pose.linear().cast<float>();
  ctx.cam_position = right_pose.translation().cast<float>();
  renderCamera(ctx, right_rays_, right_linear, nullptr);

  const std::uint64_t seed = scene_.sensor.seed * 1000003ULL + frame_index * 2ULL;
  out.left = develop(left_linear, scene_.sensor, seed);
  out.right = develop(right_linear, scene_.sensor, seed + 1);

  for (std::size_t i = 0; i < out.ground_truth.size(); ++i) {
    const cv::Mat mask = out.left_labels == static_cast<std::uint16_t>(i + 1);
    out.ground_truth[i].visible_pixels = cv::countNonZero(mask);
    if (out.ground_truth[i].visible_pixels > 0) out.ground_truth[i].roi_left = cv::boundingRect(mask);
  }
  return out;
}

}  // namespace sim
}  // namespace underwater_stereo
