// SPDX-License-Identifier: BSD-3-Clause
// The host's auto-exposure law and metering: convergence on model cameras, limits, the metered region.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "underwater_stereo/camera/auto_exposure.h"

using namespace underwater_stereo;

namespace {

/// Runs the law against a camera model (brightness of exposure x gain) from `start`; returns the last exposure.
Exposure converge(const AutoExposureSettings& s, const std::function<double(const Exposure&)>& camera, Exposure start,
                  int frames, int* steps_taken = nullptr) {
  Exposure e = start;
  int steps = 0;
  for (int k = 0; k < frames; ++k) {
    const Exposure next = nextExposure(s, camera(e), e);
    if (next.exposure_us != e.exposure_us || next.gain_db != e.gain_db) steps = k + 1;
    e = next;
  }
  if (steps_taken) *steps_taken = steps;
  return e;
}

double linearCamera(const Exposure& e, double scene) {
  return std::min(1.0, scene * e.exposure_us * std::pow(10.0, e.gain_db / 20.0));
}

}  // namespace

TEST(AutoExposure, ConvergesOnALinearCameraWithinTheDeadbandAndStaysThere) {
  AutoExposureSettings s;  // target 0.4, 100..20000 us, gain fixed at 0 dB
  const double scene = 0.4 / 5000.0;  // 5 ms gives the target
  int steps = 0;
  const Exposure e = converge(s, [&](const Exposure& x) { return linearCamera(x, scene); }, {200, 0}, 30, &steps);
  EXPECT_NEAR(linearCamera(e, scene), 0.4, 0.4 * s.deadband);
  EXPECT_LE(steps, 6) << "200 us -> 5 ms in steps of at most x2";
  EXPECT_EQ(e.gain_db, 0.0);
  // From too bright: saturation (1.0) halves per step, then converges.
  const Exposure down = converge(s, [&](const Exposure& x) { return linearCamera(x, scene); }, {20000, 0}, 30);
  EXPECT_NEAR(linearCamera(down, scene), 0.4, 0.4 * s.deadband);
}

TEST(AutoExposure, ConvergesWithoutOvershootOnTheFakeCamerasLogarithmicResponse) {
  // Aravis' fake camera: mean ~ 0.5 x (1 + gain + log10(exposure / 10 ms)).
  auto fake = [](const Exposure& x) { return 0.5 * (1 + std::log10(x.exposure_us / 10000.0)); };
  AutoExposureSettings s;
  double last = 0;
  Exposure e{2000, 0};
  for (int k = 0; k < 60; ++k) {
    const double b = fake(e);
    EXPECT_LE(b, 0.4 * (1 + s.deadband) + 1e-9) << "overshoot at frame " << k;
    EXPECT_GE(b, last - 1e-12) << "brightness went back at frame " << k;
    last = b;
    e = nextExposure(s, b, e);
  }
  EXPECT_NEAR(fake(e), 0.4, 0.4 * s.deadband);
}

TEST(AutoExposure, SpendsExposureFirstThenGainAndHoldsTheLimits) {
  AutoExposureSettings s;
  s.gain_max_db = 12;
  const double dark = 0.4 / (20000.0 * 2.0);  // needs 20 ms and x2 (6 dB)
  const Exposure e = converge(s, [&](const Exposure& x) { return linearCamera(x, dark); }, {1000, 0}, 40);
  EXPECT_DOUBLE_EQ(e.exposure_us, 20000.0);
  EXPECT_NEAR(e.gain_db, 6.02, 0.5);
  const double black = 1e-9;  // nothing helps: both at their maxima, no further change
  const Exposure m = converge(s, [&](const Exposure& x) { return linearCamera(x, black); }, {1000, 0}, 40);
  EXPECT_DOUBLE_EQ(m.exposure_us, 20000.0);
  EXPECT_DOUBLE_EQ(m.gain_db, 12.0);
  const double glare = 1.0;  // saturated at any setting: minimum exposure, minimum gain
  const Exposure g = converge(s, [&](const Exposure&) { return glare; }, {20000, 12}, 40);
  EXPECT_DOUBLE_EQ(g.exposure_us, 100.0);
  EXPECT_DOUBLE_EQ(g.gain_db, 0.0);
}

TEST(AutoExposure, MetersOnlyTheRegionSoABrightSurfaceAboveDoesNotDarkenTheBuoys) {
  cv::Mat image(400, 600, CV_8UC1, cv::Scalar(50));
  image.rowRange(0, 100).setTo(255);  // the surface: the top quarter
  AutoRoi whole{0, 0, 1, 1}, below;  // default: all but the top quarter
  EXPECT_NEAR(meanBrightness(image, below), 50.0 / 255, 1e-9);
  EXPECT_NEAR(meanBrightness(image, whole), (0.25 * 255 + 0.75 * 50) / 255, 0.01);
  AutoExposureSettings s;
  const Exposure start{5000, 0};
  s.roi = below;
  EXPECT_GT(nextExposure(s, meanBrightness(image, s.roi), start).exposure_us, 5000) << "buoys too dark: more light";
  s.roi = whole;
  EXPECT_EQ(nextExposure(s, meanBrightness(image, s.roi), start).exposure_us, 5000)
      << "the whole frame meters 0.39: inside the deadband, the buoys stay dark";
  // Bayer and RGB: every channel counts.
  cv::Mat rgb(40, 40, CV_8UC3, cv::Scalar(0, 0, 255));
  EXPECT_NEAR(meanBrightness(rgb, whole), 1.0 / 3, 1e-9);
}

TEST(AutoExposure, BadInputIsRefusedNamingIt) {
  EXPECT_THROW(meanBrightness(cv::Mat(), AutoRoi{}), std::invalid_argument);
  EXPECT_THROW(meanBrightness(cv::Mat(10, 10, CV_16UC1, cv::Scalar(0)), AutoRoi{}), std::invalid_argument);
  EXPECT_THROW(meanBrightness(cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)), AutoRoi{0.5, 0.5, 0, 0.5}), std::invalid_argument);
  EXPECT_THROW(exposureSyncFromName("auto"), std::invalid_argument);
  EXPECT_EQ(exposureSyncFromName(exposureSyncName(ExposureSync::kMasterSlave)), ExposureSync::kMasterSlave);
  AutoExposureSettings s;
  EXPECT_TRUE(s.validate("~").empty());
  s.target = 1.2;
  s.exposure_min_us = 0;
  s.gain_max_db = -1;
  s.deadband = 0.6;
  s.max_step = 1;
  s.roi = AutoRoi{0.5, 0, 0.6, 1};
  const auto p = s.validate("~");
  ASSERT_EQ(p.size(), 6U);
  EXPECT_NE(p[0].find("~auto_target"), std::string::npos) << p[0];
  EXPECT_NE(p[5].find("~auto_roi"), std::string::npos) << p[5];
}
