// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <stdexcept>

#include "underwater_stereo/sim/scene.h"

using namespace underwater_stereo::sim;

namespace {

std::string parseError(const std::string& yaml) {
  try {
    parseScene(YAML::Load(yaml));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(Scene, ParsesEveryShapeWithDefaults) {
  const Scene s = parseScene(YAML::Load(R"(
objects:
  - {name: a, shape: sphere, colour: red, position_m: [0, 0, 2], diameter_m: 0.3}
  - {name: b, shape: cylinder, colour: orange, position_m: [1, 0, 3], diameter_m: 0.1, length_m: 1.0, rpy_deg: [0, 90, 0]}
  - {name: c, shape: box, colour: yellow, position_m: [0, 1, 4], size_m: [0.2, 0.3, 0.4]}
  - {name: d, shape: plane, colour: green, position_m: [0, 0, 5], size_m: [1.0, 0.5]}
)"));
  ASSERT_EQ(s.objects.size(), 4U);
  EXPECT_EQ(s.rig.width, 1920);
  EXPECT_NEAR(s.rig.focalPx(), 8.0e-3 / 5.86e-6 * 1.333, 1e-6);
  EXPECT_EQ(s.objects[0].size_m, Eigen::Vector3d(0.3, 0.3, 0.3));
  EXPECT_EQ(s.objects[1].size_m, Eigen::Vector3d(0.1, 0.1, 1.0));
  EXPECT_EQ(s.objects[2].size_m, Eigen::Vector3d(0.2, 0.3, 0.4));
  EXPECT_EQ(s.objects[3].size_m, Eigen::Vector3d(1.0, 0.5, 0.0));
  EXPECT_EQ(s.objects[3].shape, ShapeType::kPanel);
  EXPECT_EQ(shapeName(s.objects[3].shape), "plane");
}

TEST(Scene, ListsEveryProblemAtOnce) {
  const std::string error = parseError(R"(
rig: {width: -5, baseline: 0.1}
sensor: {encoding: yuv422}
objects:
  - {name: a, shape: cone, colour: red, position_m: [0, 0, 2]}
  - {name: b, shape: sphere, position_m: [0, 0], diameter_m: abc}
)");
  EXPECT_NE(error.find("rig.baseline: unknown key"), std::string::npos) << error;
  EXPECT_NE(error.find("'cone' is not one of"), std::string::npos) << error;
  EXPECT_NE(error.find("objects[1].colour: missing"), std::string::npos) << error;
  EXPECT_NE(error.find("objects[1].position_m: expected 3 numbers, got 2"), std::string::npos) << error;
  EXPECT_NE(error.find("objects[1].diameter_m: expected a number"), std::string::npos) << error;
  // Values are checked along with what did not parse (rig.width, sensor.encoding), but not the defaults of an object
  // with a field that did not parse (objects[1]'s empty colour and zero size).
  EXPECT_NE(error.find("rig.width = -5 is outside"), std::string::npos) << error;
  EXPECT_NE(error.find("sensor.encoding: 'yuv422'"), std::string::npos) << error;
  EXPECT_EQ(error.find("objects[1] ("), std::string::npos) << error;
}

TEST(Scene, RejectsInvalidValues) {
  const std::string error = parseError(R"(
rig: {width: -5}
sensor: {encoding: yuv422}
light: {exposure: 0}
objects:
  - {name: a, shape: sphere, colour: red, position_m: [0, 0, 2], diameter_m: 0}
  - {name: a, shape: sphere, colour: red, position_m: [0, 0, 2], diameter_m: 0.2}
  - {name: b, shape: sphere, colour: red, position_m: [0, 0, 2], diameter_m: 0.2, rpy_deg: [.nan, 0, 0],
     motion: {velocity_mps: [1e30, 0, 0]}}
camera_motion: {yaw_rate_dps: .inf}
)");
  EXPECT_NE(error.find("rig.width"), std::string::npos) << error;
  EXPECT_NE(error.find("sensor.encoding: 'yuv422'"), std::string::npos) << error;
  EXPECT_NE(error.find("light.exposure"), std::string::npos) << error;
  EXPECT_NE(error.find("size_m[0]"), std::string::npos) << error;
  EXPECT_NE(error.find("is used twice"), std::string::npos) << error;
  EXPECT_NE(error.find("objects[2] (b).rpy_deg[0] = nan is outside [-3600, 3600]"), std::string::npos) << error;
  EXPECT_NE(error.find("objects[2] (b).motion.velocity_mps[0] = 1e+30 is outside [-100, 100]"), std::string::npos) << error;
  EXPECT_NE(error.find("camera_motion.yaw_rate_dps = inf"), std::string::npos) << error;
  // A Bayer head of odd size: the detector could not read its images.
  EXPECT_NE(parseError("rig: {width: 641, height: 400}").find("rig.width and rig.height must be even"), std::string::npos);
  EXPECT_EQ(parseError("rig: {width: 640, height: 400}"), "");
}

TEST(Scene, RejectsNonMapDocumentAndMissingFile) {
  EXPECT_THROW(parseScene(YAML::Load("[1, 2, 3]")), std::invalid_argument);
  EXPECT_THROW(loadSceneFile("/nonexistent/scene.yaml"), std::invalid_argument);
}

TEST(Scene, EmptySceneIsValid) {
  const Scene s = parseScene(YAML::Load("name: empty"));
  EXPECT_TRUE(s.objects.empty());
  EXPECT_TRUE(s.validate().empty());
}
