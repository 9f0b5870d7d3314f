// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <cmath>
#include <set>

#include "sim_test_helpers.h"
#include "underwater_stereo/sim/renderer.h"
#include "underwater_stereo/sim/scene_sampler.h"

using namespace underwater_stereo::sim;

namespace {

/// Small images keep the tests quick; the field of view is the real head's.
SceneSamplerConfig smallConfig() {
  SceneSamplerConfig c;
  c.width = 320;
  c.height = 200;
  return c;
}

const ColourFamily& familyOf(const std::string& name) {
  for (const auto& f : colourFamilies()) {
    if (f.name == name) return f;
  }
  throw std::invalid_argument(name);
}

bool albedoInFamily(const Eigen::Vector3d& albedo, const ColourFamily& f) {
  // Sampled corners of the family's HSV box span the albedos it may give; check the albedo against the box
  // by converting back to sRGB HSV.
  Eigen::Vector3d srgb;
  for (int i = 0; i < 3; ++i) {
    const double l = albedo[i];
    srgb[i] = l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
  }
  const double v = srgb.maxCoeff(), c = v - srgb.minCoeff(), s = v > 0 ? c / v : 0;
  const double eps = 1e-6;
  if (v < f.value.first - eps || v > f.value.second + eps || s < f.saturation.first - eps ||
      s > f.saturation.second + eps) {
    return false;
  }
  if (c < 1e-9 || f.hue_deg.second - f.hue_deg.first >= 360.0) return true;
  double h = 0;
  if (v == srgb.x()) h = 60.0 * std::fmod((srgb.y() - srgb.z()) / c, 6.0);
  else if (v == srgb.y()) h = 60.0 * ((srgb.z() - srgb.x()) / c + 2.0);
  else h = 60.0 * ((srgb.x() - srgb.y()) / c + 4.0);
  for (const double wrap : {-360.0, 0.0, 360.0}) {
    if (h + wrap >= f.hue_deg.first - 1e-6 && h + wrap <= f.hue_deg.second + 1e-6) return true;
  }
  return false;
}

}  // namespace

TEST(SceneSampler, SameSeedGivesTheSameSceneAndOthersDiffer) {
  const SampledScene a = sampleScene(1234, smallConfig()), b = sampleScene(1234, smallConfig());
  const SampledScene c = sampleScene(1235, smallConfig());
  ASSERT_EQ(a.scene.objects.size(), b.scene.objects.size());
  EXPECT_EQ(a.turbidity, b.turbidity);
  EXPECT_EQ(a.scene.light.exposure, b.scene.light.exposure);
  EXPECT_EQ(a.scene.water.attenuation_per_m, b.scene.water.attenuation_per_m);
  for (std::size_t i = 0; i < a.scene.objects.size(); ++i) {
    EXPECT_EQ(a.scene.objects[i].name, b.scene.objects[i].name);
    EXPECT_EQ(a.scene.objects[i].position_m, b.scene.objects[i].position_m);
    EXPECT_EQ(a.scene.objects[i].albedo, b.scene.objects[i].albedo);
  }
  const cv::Mat left_a = Renderer(a.scene).render(0.0, 0).left, left_b = Renderer(b.scene).render(0.0, 0).left;
  EXPECT_EQ(cv::norm(left_a, left_b, cv::NORM_INF), 0.0);
  EXPECT_NE(a.turbidity, c.turbidity);
  EXPECT_NE(a.scene.objects[0].position_m, c.scene.objects[0].position_m);
}

TEST(SceneSampler, EveryParameterIsWithinItsDocumentedRange) {
  const SceneSamplerConfig config = smallConfig();
  int designated_total = 0, distractor_total = 0;
  for (std::uint64_t seed = 0; seed < 60; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const SampledScene s = sampleScene(seed, config);
    EXPECT_TRUE(s.scene.validate().empty());
    EXPECT_EQ(s.scene.rig.width, 320);
    EXPECT_GE(s.turbidity, config.turbidity.first);
    EXPECT_LE(s.turbidity, config.turbidity.second);
    EXPECT_GE(s.water_type, config.water_type.first);
    EXPECT_LE(s.water_type, config.water_type.second);
    EXPECT_GE(s.target_luma, config.target_luma.first);
    EXPECT_LE(s.target_luma, config.target_luma.second);
    EXPECT_EQ(s.scene.sensor.encoding, "bayer_rggb8");
    // Water: attenuation from clear (0.05 /m) to murky, red lost faster than green in every water type.
    EXPECT_GT(s.scene.water.attenuation_per_m.minCoeff(), 0.04);
    EXPECT_LT(s.scene.water.attenuation_per_m.maxCoeff(), 1.0);
    EXPECT_GT(s.scene.water.attenuation_per_m.x(), s.scene.water.attenuation_per_m.y());
    EXPECT_GT(s.scene.light.sun_direction.y(), 0.8);  // from above, within 35 deg of vertical
    ASSERT_EQ(s.designated.size(), s.scene.objects.size());
    int designated = 0, distractors = 0;
    for (std::size_t i = 0; i < s.scene.objects.size(); ++i) {
      const SceneObject& o = s.scene.objects[i];
      const auto& names = s.designated[i] ? config.designated : config.distractor_colours;
      EXPECT_NE(std::find(names.begin(), names.end(), o.colour), names.end()) << o.name;
      EXPECT_TRUE(albedoInFamily(o.albedo, familyOf(o.colour))) << o.name << " albedo " << o.albedo.transpose();
      const double largest = o.size_m.maxCoeff();
      EXPECT_GE(largest, config.size_m.first - 1e-9) << o.name;
      EXPECT_LE(largest, config.size_m.second + 1e-9) << o.name;
      const double range = o.position_m.norm();
      EXPECT_GE(range, config.range_m.first - 1e-9) << o.name;
      EXPECT_LE(range, config.range_m.second + 1e-9) << o.name;
      EXPECT_GT(o.position_m.z(), 0.0) << o.name << " is behind the camera";
      (s.designated[i] ? designated : distractors)++;
    }
    EXPECT_GE(designated, config.designated_objects.first);
    EXPECT_LE(designated, config.designated_objects.second);
    EXPECT_LE(distractors, config.distractors.second);
    designated_total += designated;
    distractor_total += distractors;
  }
  EXPECT_GT(distractor_total, 30);  // the distractors are there (not all lost to placement)
  EXPECT_GT(designated_total, 100);
}

TEST(SceneSampler, ObjectsDoNotIntersectEachOtherOrTheSeabedOrTheCamera) {
  for (std::uint64_t seed = 100; seed < 160; ++seed) {
    const Scene s = sampleScene(seed, smallConfig()).scene;
    for (std::size_t i = 0; i < s.objects.size(); ++i) {
      const SceneObject& a = s.objects[i];
      const double ra = boundingRadius(a);
      EXPECT_GT(a.position_m.norm() - ra, 0.2) << "seed " << seed << " " << a.name << " reaches the camera";
      if (s.seabed.enabled) {
        EXPECT_LT(a.position_m.y() + ra, s.seabed.depth_m) << "seed " << seed << " " << a.name << " in the seabed";
      }
      for (std::size_t j = 0; j < i; ++j) {
        const SceneObject& b = s.objects[j];
        EXPECT_GT((a.position_m - b.position_m).norm(), ra + boundingRadius(b))
            << "seed " << seed << ": " << a.name << " and " << b.name << " intersect";
      }
    }
  }
}

TEST(SceneSampler, ScenesShowOcclusionBorderCutsAndEveryShapeAndColour) {
  int occluded = 0, cut = 0;
  std::set<std::string> shapes, colours;
  const Renderer head(sampleScene(200, smallConfig()).scene);
  for (std::uint64_t seed = 200; seed < 240; ++seed) {
    const SampledScene s = sampleScene(seed, smallConfig());
    const RenderedPair pair = head.withScene(s.scene).render(0.0, 0);
    for (std::size_t i = 0; i < pair.ground_truth.size(); ++i) {
      const GroundTruthObject& g = pair.ground_truth[i];
      shapes.insert(g.shape);
      colours.insert(g.colour);
      if (g.visible_pixels == 0) continue;
      const cv::Rect r = g.roi_left;
      cut += r.x == 0 || r.y == 0 || r.br().x == 320 || r.br().y == 200;
      // Alone in the scene it would show more pixels: something is in front of it.
      Scene alone = s.scene;
      alone.objects = {s.scene.objects[i]};
      occluded += head.withScene(alone).render(0.0, 0).ground_truth[0].visible_pixels > g.visible_pixels + 20;
    }
  }
  EXPECT_GT(occluded, 3);
  EXPECT_GT(cut, 5);
  EXPECT_EQ(shapes.size(), 4U);
  EXPECT_EQ(colours.size(), colourFamilies().size());
}

TEST(SceneSampler, AutoExposureReachesItsTargetBrightness) {
  for (std::uint64_t seed = 300; seed < 310; ++seed) {
    const SampledScene s = sampleScene(seed, smallConfig());
    Scene clean = s.scene;
    clean.sensor.encoding = "bgr8";
    clean.sensor.noise_sigma = 0.0;
    const double luma = meanLuma(Renderer(clean).render(0.0, 0).left);
    EXPECT_NEAR(luma, s.target_luma, 0.1 * s.target_luma + 3.0) << "seed " << seed;
  }
}

TEST(SceneSampler, AlbedoFromHsvIsLinearSrgb) {
  EXPECT_LT((albedoFromHsv(0, 1, 1) - Eigen::Vector3d(1, 0, 0)).norm(), 1e-12);
  EXPECT_LT((albedoFromHsv(120, 1, 1) - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);
  EXPECT_LT((albedoFromHsv(-120, 1, 1) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
  // sRGB 0.5 grey is 21.4 % linear reflectance.
  EXPECT_NEAR(albedoFromHsv(0, 0, 0.5).x(), 0.214, 1e-3);
}

// Optics drawn from ranges (other heads) come from a stream of their own: with the head's lens and baseline as a range
// the scene is the one fixed optics give, draw for draw; a wider range gives each seed its own optics, within it.
TEST(SceneSampler, OpticsAreDrawnWithinTheirRangesWithoutMovingTheOtherDraws) {
  SceneSamplerConfig fixed = smallConfig(), same = smallConfig(), varied = smallConfig();
  same.focal_length_mm = {RigConfig{}.focal_length_mm, RigConfig{}.focal_length_mm};
  same.baseline_m = {RigConfig{}.baseline_m, RigConfig{}.baseline_m};
  EXPECT_FALSE(same.variesOptics());
  varied.focal_length_mm = {4.0, 16.0};
  varied.baseline_m = {0.06, 0.3};
  EXPECT_TRUE(varied.variesOptics());
  std::set<double> focal, baseline;
  for (std::uint64_t seed = 4000; seed < 4010; ++seed) {
    const SampledScene a = sampleScene(seed, fixed), b = sampleScene(seed, same), v = sampleScene(seed, varied);
    EXPECT_EQ(a.scene.rig.focal_length_mm, RigConfig{}.focal_length_mm);
    EXPECT_EQ(a.turbidity, b.turbidity);
    EXPECT_EQ(a.target_luma, b.target_luma);
    ASSERT_EQ(a.scene.objects.size(), b.scene.objects.size());
    for (std::size_t i = 0; i < a.scene.objects.size(); ++i) EXPECT_EQ(a.scene.objects[i].position_m, b.scene.objects[i].position_m);
    EXPECT_EQ(a.turbidity, v.turbidity);  // drawn before the objects, whose placement depends on the optics
    EXPECT_GE(v.scene.rig.focal_length_mm, 4.0);
    EXPECT_LE(v.scene.rig.focal_length_mm, 16.0);
    EXPECT_GE(v.scene.rig.baseline_m, 0.06);
    EXPECT_LE(v.scene.rig.baseline_m, 0.3);
    EXPECT_EQ(sampleScene(seed, varied).scene.rig.baseline_m, v.scene.rig.baseline_m);
    focal.insert(v.scene.rig.focal_length_mm);
    baseline.insert(v.scene.rig.baseline_m);
  }
  EXPECT_EQ(focal.size(), 10U);
  EXPECT_EQ(baseline.size(), 10U);
  varied.baseline_m = {0.3, 0.06};
  varied.focal_length_mm = {0.5, 8.0};
  EXPECT_EQ(varied.validate().size(), 2U);
}

TEST(SceneSampler, InvalidConfigIsRefusedWithEveryProblem) {
  SceneSamplerConfig c;
  c.range_m = {5.0, 0.5};
  c.turbidity = {0.0, 2.0};
  c.designated = {"red", "magenta"};
  c.distractor_colours = {"red"};
  const std::vector<std::string> problems = c.validate();
  EXPECT_EQ(problems.size(), 4U);
  EXPECT_THROW(sampleScene(1, c), std::invalid_argument);
  EXPECT_THROW(downscaledScene(Scene{}, 0), std::invalid_argument);
  Scene s;
  EXPECT_THROW(autoExpose(s, 300.0), std::invalid_argument);
}

TEST(Renderer, CausticsModulateSunlitSurfacesWithoutChangingTheirMean) {
  Scene s = test::smallScene(test::sphere("ball", {0, 0, 3}, 0.3));
  s.objects.clear();
  s.light.lamp_intensity = 0.0;
  s.seabed.texture = 0.0;
  s.seabed.depth_m = 1.0;
  cv::Mat flat, with;
  cv::cvtColor(Renderer(s).render(0.0, 0).left, flat, cv::COLOR_BGR2GRAY);
  s.light.caustics = 1.0;
  cv::cvtColor(Renderer(s).render(0.0, 0).left, with, cv::COLOR_BGR2GRAY);
  const cv::Rect floor(0, 300, 640, 100);  // the lower image rows see the seabed
  cv::Scalar mean_flat, sd_flat, mean_with, sd_with;
  cv::meanStdDev(flat(floor), mean_flat, sd_flat);
  cv::meanStdDev(with(floor), mean_with, sd_with);
  EXPECT_NEAR(mean_with[0], mean_flat[0], 0.15 * mean_flat[0]);
  EXPECT_GT(sd_with[0], sd_flat[0] + 3.0);
}

TEST(Renderer, WhiteBalanceAndSpecularChangeWhatTheyShould) {
  Scene s = test::smallScene(test::sphere("ball", {0, 0, 1.5}, 0.4));
  s.objects[0].albedo = {0.3, 0.3, 0.3};
  s.objects[0].texture = 0.0;
  const RenderedPair plain = Renderer(s).render(0.0, 0);
  s.sensor.white_balance = {1.5, 1.0, 1.0};
  const RenderedPair warm = Renderer(s).render(0.0, 0);
  const cv::Mat ball = plain.left_labels == 1;
  EXPECT_GT(cv::mean(warm.left, ball)[2], cv::mean(plain.left, ball)[2] + 10.0);   // red up
  EXPECT_NEAR(cv::mean(warm.left, ball)[1], cv::mean(plain.left, ball)[1], 0.5);    // green kept
  s.sensor.white_balance = {1.0, 1.0, 1.0};
  s.objects[0].specular = 0.5;
  s.objects[0].shininess = 100.0;
  const RenderedPair glossy = Renderer(s).render(0.0, 0);
  double plain_max = 0, glossy_max = 0;
  cv::Mat grey;
  cv::cvtColor(plain.left, grey, cv::COLOR_BGR2GRAY);
  cv::minMaxLoc(grey, nullptr, &plain_max, nullptr, nullptr, ball);
  cv::cvtColor(glossy.left, grey, cv::COLOR_BGR2GRAY);
  cv::minMaxLoc(grey, nullptr, &glossy_max, nullptr, nullptr, ball);
  EXPECT_GT(glossy_max, plain_max + 20.0);  // the lamp's highlight
}
