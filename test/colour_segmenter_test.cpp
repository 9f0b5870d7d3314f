// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "underwater_stereo/detection/colour_segmenter.h"

using namespace underwater_stereo;

namespace {

cv::Scalar bgrOfHsv(int h, int s, int v) {
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(h, s, v)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  const cv::Vec3b p = bgr.at<cv::Vec3b>(0, 0);
  return cv::Scalar(p[0], p[1], p[2]);
}

ColourMaskConfig redAndGreen() {
  ColourMaskConfig c;
  c.grey_world = false;
  c.classes = {{"red", 170, 10, 80, 255, 40, 255}, {"green", 45, 85, 80, 255, 40, 255}};
  return c;
}

}  // namespace

TEST(ColourSegmenter, RedHueWrapsThroughZero) {
  cv::Mat img(100, 300, CV_8UC3, bgrOfHsv(100, 150, 150));  // blue-cyan water
  cv::circle(img, {50, 50}, 30, bgrOfHsv(175, 200, 200), cv::FILLED);   // red below 180
  cv::circle(img, {150, 50}, 30, bgrOfHsv(4, 200, 200), cv::FILLED);    // red above 0
  cv::circle(img, {250, 50}, 30, bgrOfHsv(60, 200, 200), cv::FILLED);   // green
  const auto masks = colourMasks(img, redAndGreen());
  ASSERT_EQ(masks.size(), 2U);
  EXPECT_EQ(masks[0].at<std::uint8_t>(50, 50), 255);
  EXPECT_EQ(masks[0].at<std::uint8_t>(50, 150), 255);
  EXPECT_EQ(masks[0].at<std::uint8_t>(50, 250), 0);
  EXPECT_EQ(masks[1].at<std::uint8_t>(50, 250), 255);
  EXPECT_EQ(masks[1].at<std::uint8_t>(50, 50), 0);
  EXPECT_NEAR(cv::countNonZero(masks[1]), M_PI * 30 * 30, 0.05 * M_PI * 30 * 30);
}

TEST(ColourSegmenter, OpeningRemovesSpecksAndClosingFillsHoles) {
  cv::Mat img(200, 200, CV_8UC3, bgrOfHsv(100, 150, 150));
  cv::rectangle(img, {20, 20, 6, 6}, bgrOfHsv(60, 200, 200), cv::FILLED);    // 6x6 speck < 10x10
  cv::rectangle(img, {80, 80, 80, 80}, bgrOfHsv(60, 200, 200), cv::FILLED);  // object...
  cv::rectangle(img, {115, 115, 5, 5}, bgrOfHsv(100, 150, 150), cv::FILLED); // ...with a small hole
  const cv::Mat green = colourMasks(img, redAndGreen())[1];
  EXPECT_EQ(cv::countNonZero(green(cv::Rect(0, 0, 60, 60))), 0);
  EXPECT_EQ(green.at<std::uint8_t>(117, 117), 255);
  EXPECT_EQ(cv::countNonZero(green), 80 * 80);

  ColourMaskConfig no_morphology = redAndGreen();
  no_morphology.open_kernel_px = 0;
  no_morphology.close_kernel_px = 0;
  const cv::Mat raw = colourMasks(img, no_morphology)[1];
  EXPECT_EQ(cv::countNonZero(raw(cv::Rect(0, 0, 60, 60))), 36);
  EXPECT_EQ(raw.at<std::uint8_t>(117, 117), 0);
}

TEST(ColourSegmenter, GreyWorldUndoesAColourCast) {
  cv::Mat img(100, 100, CV_8UC3, cv::Scalar(160, 140, 40));  // cyan water cast
  img(cv::Rect(0, 0, 50, 100)).setTo(cv::Scalar(120, 100, 30));
  const cv::Scalar mean = cv::mean(greyWorld(img));
  EXPECT_NEAR(mean[0], mean[2], 2.0);
  EXPECT_NEAR(mean[1], mean[2], 2.0);
}

TEST(ColourSegmenter, GarbageInputThrows) {
  EXPECT_THROW(colourMasks(cv::Mat(), redAndGreen()), std::invalid_argument);
  EXPECT_THROW(colourMasks(cv::Mat(5, 5, CV_8UC1, cv::Scalar(0)), redAndGreen()), std::invalid_argument);
  EXPECT_THROW(greyWorld(cv::Mat(5, 5, CV_16UC3, cv::Scalar(0))), std::invalid_argument);
}

TEST(ColourSegmenter, InvalidConfigListsEveryProblem) {
  ColourMaskConfig c = redAndGreen();
  EXPECT_TRUE(c.validate().empty());
  c.classes[1].name = "red";
  c.classes[0].hue_max = 200;
  c.classes[0].saturation_min = 300;
  c.open_kernel_px = -1;
  // duplicate name, hue out of range, saturation out of range and min > max, kernel size
  EXPECT_EQ(c.validate().size(), 5U);
  EXPECT_FALSE(ColourMaskConfig{}.validate().empty()) << "no designated colour";
}
