// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <limits>

#include "underwater_stereo/sim/stereo_rig.h"

using namespace underwater_stereo;

namespace {

StereoCalibration rigCalibration() { return sim::StereoRig(sim::RigConfig{}).calibration(); }

bool mentions(const std::vector<std::string>& problems, const std::string& text) {
  for (const auto& p : problems) {
    if (p.find(text) != std::string::npos) return true;
  }
  return false;
}

}  // namespace

TEST(StereoCalibration, RigCalibrationIsValidWithTheConfiguredBaseline) {
  const StereoCalibration c = rigCalibration();
  EXPECT_TRUE(c.validate().empty());
  EXPECT_NEAR(c.baselineM(), 0.12, 0.003);  // the right camera is slightly off the ideal x axis
  EXPECT_EQ(c.left.P(0, 3), 0.0);
  EXPECT_NEAR(c.disparityAtDepth(0.5) / c.disparityAtDepth(5.0), 10.0, 1e-9);
}

TEST(StereoCalibration, UncalibratedCameraIsRejected) {
  StereoCalibration c = rigCalibration();
  c.left.K = cv::Matx33d::zeros();
  EXPECT_TRUE(mentions(c.validate(), "left: K[0] (fx) = 0 px is outside 50..20000 (camera not calibrated)"));
}

TEST(StereoCalibration, NanIsRejected) {
  StereoCalibration c = rigCalibration();
  c.right.P(0, 2) = std::numeric_limits<double>::quiet_NaN();
  c.left.D[0] = std::numeric_limits<double>::infinity();
  const auto problems = c.validate();
  EXPECT_TRUE(mentions(problems, "right: K, R or P contains NaN"));
  EXPECT_TRUE(mentions(problems, "left: D contains NaN"));
}

TEST(StereoCalibration, PairProblemsAreRejected) {
  StereoCalibration c = rigCalibration();
  c.right.width = 2000;
  c.left.P(0, 3) = 5.0;
  c.right.P(0, 3) = 10.0;
  const auto problems = c.validate();
  EXPECT_TRUE(mentions(problems, "left is 1920x1200 but right is 2000x1200"));
  EXPECT_TRUE(mentions(problems, "left P[3] must be 0"));
  EXPECT_TRUE(mentions(problems, "no positive baseline"));
}

TEST(StereoCalibration, BadSizeDistortionAndRotationAreRejected) {
  CameraCalibration c = rigCalibration().left;
  c.width = 0;
  c.D = {0.1, 0.2};
  c.R(0, 0) = 3.0;
  const auto problems = c.validate("cam");
  EXPECT_TRUE(mentions(problems, "cam: calibrated image size 0x1200 is outside 32..16384"));
  EXPECT_TRUE(mentions(problems, "D has 2 coefficients"));
  EXPECT_TRUE(mentions(problems, "R is not a rotation"));
}
