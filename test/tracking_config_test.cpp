// SPDX-License-Identifier: BSD-3-Clause
// Tracking configuration, targets and the camera's view.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "underwater_stereo/sim/stereo_rig.h"
#include "underwater_stereo/tracking/camera_view.h"
#include "underwater_stereo/tracking/target_matcher.h"
#include "underwater_stereo/tracking/tracking_config.h"

using namespace underwater_stereo;

namespace {

std::string problemsOf(const std::string& yaml) {
  try {
    parseTrackingConfig(YAML::Load(yaml));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(TrackingConfig, PackageFileLoads) {
  const TrackingConfig c = loadTrackingConfigFile(std::string(UWS_SOURCE_DIR) + "/config/tracking.yaml");
  EXPECT_TRUE(c.validate().empty());
  ASSERT_NE(c.target("red_buoy"), nullptr);
  EXPECT_EQ(c.target("red_buoy")->colour, "red");
  EXPECT_EQ(c.target("nothing"), nullptr);
}

TEST(TrackingConfig, ParsesTargetsAndSettings) {
  const TrackingConfig c = parseTrackingConfig(YAML::Load(
      "targets: [{name: a, colour: red, shape: sphere, size_m: 0.25, size_tolerance: 0.2}, {name: b, colour: green, "
      "size_m: 1}]\ntargets_only: true\ntracking: {confirm_hits: 5, max_misses: 7, gate_chi2: 9}"));
  ASSERT_EQ(c.targets.size(), 2U);
  EXPECT_EQ(c.targets[0].shape, ShapeKind::kSphere);
  EXPECT_DOUBLE_EQ(c.targets[0].size_tolerance, 0.2);
  EXPECT_EQ(c.targets[1].shape, ShapeKind::kUnknown) << "no shape: any";
  for (const char* any : {"\"\"", "unknown"}) {
    const std::string yaml = std::string("targets: [{name: a, colour: red, size_m: 1, shape: ") + any + "}]";
    EXPECT_EQ(parseTrackingConfig(YAML::Load(yaml)).targets[0].shape, ShapeKind::kUnknown) << any;
  }
  EXPECT_TRUE(c.targets_only);
  EXPECT_EQ(c.confirm_hits, 5);
  EXPECT_EQ(c.max_misses, 7);
  EXPECT_DOUBLE_EQ(c.gate_chi2, 9.0);
  const TrackingConfig scaled = parseTrackingConfig(YAML::Load("tracking: {cut_by_border_sigma_scale: 3}"));
  EXPECT_DOUBLE_EQ(scaled.cut_by_border_sigma_scale, 3.0);
}

TEST(TrackingConfig, ListsEveryProblem) {
  const std::string p = problemsOf(
      "targets: [{name: a, colour: red, shape: cone, size_m: -1, size_tolerance: 2}, {name: a, size_m: x}]\n"
      "tracking: {confirm_hits: 0, gate_chi2: -1, max_misses: 0, cut_by_border_sigma_scale: 0.5, bogus: 1}\nextra: 1");
  for (const char* expected : {"targets[0].shape: 'cone' is not one of sphere, cylinder, box, plane, unknown",
                               "targets[0].size_m", "targets[0].size_tolerance",
                               "targets[1].colour: missing", "targets[1].size_m: expected a number",
                               "targets[1].name: 'a' used twice", "tracking.confirm_hits", "tracking.gate_chi2",
                               "tracking.max_misses", "tracking.cut_by_border_sigma_scale must be >= 1",
                               "tracking.bogus: unknown key", "extra: unknown key"}) {
    EXPECT_NE(p.find(expected), std::string::npos) << expected << " not in:\n" << p;
  }
  EXPECT_NE(problemsOf("targets_only: true").find("needs at least one target"), std::string::npos);
  EXPECT_NE(problemsOf("targets: 3").find("expected a list"), std::string::npos);
  EXPECT_THROW(loadTrackingConfigFile("/nonexistent/tracking.yaml"), std::invalid_argument);
}

TEST(TargetMatcher, LabelsBySizeColourAndShape) {
  TrackingConfig c;
  c.targets = {{"small", "red", ShapeKind::kSphere, 0.2, 0.2}, {"large", "red", ShapeKind::kSphere, 0.5, 0.2},
               {"tube", "orange", ShapeKind::kUnknown, 0.9, 0.3}};
  const TargetMatcher m(c);
  EXPECT_EQ(m.match("red", ShapeKind::kSphere, Eigen::Vector3d::Constant(0.21)).target, 0);
  EXPECT_EQ(m.match("red", ShapeKind::kUnknown, Eigen::Vector3d::Constant(0.45)).target, 1);
  const TargetMatch wrong = m.match("red", ShapeKind::kSphere, Eigen::Vector3d::Constant(0.33));
  EXPECT_EQ(wrong.fit, TargetFit::kWrongSize);
  EXPECT_FALSE(m.keep(wrong));
  const TargetMatch box = m.match("red", ShapeKind::kBox, Eigen::Vector3d::Constant(0.2));
  EXPECT_EQ(box.fit, TargetFit::kNoTarget);
  EXPECT_TRUE(m.keep(box));
  EXPECT_EQ(m.match("orange", ShapeKind::kCylinder, {0.1, 0.1, 0.85}).target, 2);  // the largest extent counts
  EXPECT_EQ(m.match("red", ShapeKind::kSphere, Eigen::Vector3d::Constant(std::nan(""))).fit, TargetFit::kWrongSize);
  c.targets_only = true;
  EXPECT_FALSE(TargetMatcher(c).keep(box));
  EXPECT_TRUE(TargetMatcher(c).keep(m.match("red", ShapeKind::kSphere, Eigen::Vector3d::Constant(0.2))));
  c.targets_only = false;
  c.reject_wrong_size = false;
  EXPECT_TRUE(TargetMatcher(c).keep(wrong));
  c.targets[0].size_m = 0;
  EXPECT_THROW(TargetMatcher{c}, std::invalid_argument);
}

TEST(CameraView, SeesTheWorkspaceInsideTheImage) {
  const CameraCalibration left = sim::StereoRig(sim::RigConfig{}).calibration().left;
  const CameraView view(left, 0.5, 5.0, 40.0);
  EXPECT_TRUE(view.sees({0, 0, 2}));
  EXPECT_FALSE(view.sees({0, 0, 6}));
  EXPECT_FALSE(view.sees({0, 0, 0.3}));
  EXPECT_FALSE(view.sees({0, 0, -2}));
  EXPECT_FALSE(view.sees({1.1, 0, 2}));  // 1820 px * 0.55 = 1000 px right of centre: outside 1920
  EXPECT_TRUE(view.sees({0.45, 0.3, 2}));
  EXPECT_FALSE(view.sees({std::nan(""), 0, 2}));
  EXPECT_THROW(CameraView(left, 5.0, 1.0, 40.0), std::invalid_argument);
  EXPECT_THROW(CameraView(CameraCalibration{}, 0.5, 5.0, 40.0), std::invalid_argument);
}
