// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "underwater_stereo/detection/image_quality.h"

using namespace underwater_stereo;

namespace {

cv::Mat uniform(int b, int g, int r) { return cv::Mat(120, 160, CV_8UC3, cv::Scalar(b, g, r)); }

}  // namespace

TEST(ImageQuality, MeanBrightnessIsBt601Luma) {
  const QualityReport r = assessQuality(uniform(40, 100, 200), QualityConfig{});
  EXPECT_NEAR(r.mean_brightness, 0.299 * 200 + 0.587 * 100 + 0.114 * 40, 0.6);
  EXPECT_EQ(r.status, QualityStatus::kOk);
  EXPECT_FALSE(r.enhanced);
}

TEST(ImageQuality, OnePassGivesOpenCVsLumaMeanAndValueCounts) {
  cv::RNG rng(3);
  for (const cv::Size size : {cv::Size(960, 600), cv::Size(7, 3), cv::Size(1, 1)}) {
    cv::Mat bgr(size, CV_8UC3);
    rng.fill(bgr, cv::RNG::UNIFORM, 0, 256);
    QualityConfig config;
    const QualityReport r = assessQuality(bgr, config);
    cv::Mat luma, channels[3], value;
    cv::cvtColor(bgr, luma, cv::COLOR_BGR2GRAY);
    cv::split(bgr, channels);
    cv::max(cv::max(channels[0], channels[1]), channels[2], value);
    EXPECT_DOUBLE_EQ(r.mean_brightness, cv::mean(luma)[0]) << size;
    EXPECT_DOUBLE_EQ(r.dark_fraction, cv::countNonZero(value < config.dark_pixel_value) / double(bgr.total()));
    EXPECT_DOUBLE_EQ(r.bright_fraction, cv::countNonZero(value > config.bright_pixel_value) / double(bgr.total()));
  }
}

TEST(ImageQuality, FramesAreSpoiledOutsideTheirGates) {
  QualityConfig config;  // the defaults: dark under 10, bright over 240 (the paper's 20 and 200 widened)
  EXPECT_EQ(assessQuality(uniform(9, 9, 9), config).status, QualityStatus::kTooDark);
  EXPECT_EQ(assessQuality(uniform(11, 11, 11), config).status, QualityStatus::kOk);
  EXPECT_EQ(assessQuality(uniform(245, 245, 245), config).status, QualityStatus::kTooBright);
  EXPECT_EQ(assessQuality(uniform(235, 235, 235), config).status, QualityStatus::kOk);
  EXPECT_TRUE(assessQuality(uniform(9, 9, 9), config).spoiled());
  EXPECT_TRUE(assessQuality(uniform(245, 245, 245), config).spoiled());
  config.too_dark_below = 20.0;  // the paper's gates
  config.too_bright_above = 200.0;
  EXPECT_EQ(assessQuality(uniform(15, 15, 15), config).status, QualityStatus::kTooDark);
  EXPECT_EQ(assessQuality(uniform(21, 21, 21), config).status, QualityStatus::kOk);
  EXPECT_EQ(assessQuality(uniform(210, 210, 210), config).status, QualityStatus::kTooBright);
  EXPECT_EQ(assessQuality(uniform(199, 199, 199), config).status, QualityStatus::kOk);
  EXPECT_EQ(qualityStatusName(QualityStatus::kTooBright), "TOO_BRIGHT");
}

TEST(ImageQuality, DimButUsableFrameIsMarkedForEnhancement) {
  const QualityReport r = assessQuality(uniform(30, 30, 30), QualityConfig{});
  EXPECT_EQ(r.status, QualityStatus::kOk);
  EXPECT_TRUE(r.enhanced);
}

TEST(ImageQuality, DarkAndBrightFractionsCountHsvValue) {
  cv::Mat img = uniform(100, 100, 100);
  img(cv::Rect(0, 0, 40, 120)).setTo(cv::Scalar(5, 10, 20));      // V = 20 < 30: dark (1/4 of the image)
  img(cv::Rect(40, 0, 16, 120)).setTo(cv::Scalar(10, 10, 250));   // V = 250 > 240: bright (1/10)
  const QualityReport r = assessQuality(img, QualityConfig{});
  EXPECT_NEAR(r.dark_fraction, 0.25, 1e-9);
  EXPECT_NEAR(r.bright_fraction, 0.1, 1e-9);
}

TEST(ImageQuality, EnhancementStretchesContrastAndKeepsHue) {
  // A dim, low-contrast orange-red texture: V between 35 and 45.
  cv::Mat value(200, 200, CV_8UC1);
  cv::RNG(7).fill(value, cv::RNG::UNIFORM, 35, 46);
  cv::Mat hsv_in;
  cv::merge(std::vector<cv::Mat>{cv::Mat(value.size(), CV_8UC1, cv::Scalar(8)),
                                 cv::Mat(value.size(), CV_8UC1, cv::Scalar(200)), value},
            hsv_in);
  cv::Mat img;
  cv::cvtColor(hsv_in, img, cv::COLOR_HSV2BGR);
  const cv::Mat out = enhanceContrast(img, QualityConfig{});
  cv::Mat grey_in, grey_out;
  cv::cvtColor(img, grey_in, cv::COLOR_BGR2GRAY);
  cv::cvtColor(out, grey_out, cv::COLOR_BGR2GRAY);
  cv::Scalar mean_in, std_in, mean_out, std_out;
  cv::meanStdDev(grey_in, mean_in, std_in);
  cv::meanStdDev(grey_out, mean_out, std_out);
  EXPECT_GT(std_out[0], 2.0 * std_in[0]);
  EXPECT_GT(mean_out[0], mean_in[0]);
  cv::Mat hsv;
  cv::cvtColor(out, hsv, cv::COLOR_BGR2HSV);
  EXPECT_NEAR(cv::mean(hsv)[0], 8, 2);  // hue kept
}

TEST(ImageQuality, GarbageInputThrows) {
  const QualityConfig config;
  EXPECT_THROW(assessQuality(cv::Mat(), config), std::invalid_argument);
  EXPECT_THROW(assessQuality(cv::Mat(10, 10, CV_8UC1, cv::Scalar(0)), config), std::invalid_argument);
  EXPECT_THROW(assessQuality(cv::Mat(10, 10, CV_32FC3, cv::Scalar(0)), config), std::invalid_argument);
  EXPECT_THROW(enhanceContrast(cv::Mat(), config), std::invalid_argument);
}

TEST(ImageQuality, InvalidConfigListsEveryProblem) {
  QualityConfig c;
  c.too_dark_below = 245;  // over too_bright_above (240)
  c.dark_pixel_value = 250;
  c.clahe_clip_limit = 0;
  c.clahe_tiles = 0;
  c.enhance_below = -1;
  EXPECT_EQ(c.validate().size(), 5U);
  EXPECT_TRUE(QualityConfig{}.validate().empty());
}
