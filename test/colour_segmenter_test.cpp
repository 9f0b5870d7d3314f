// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <random>

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
  c.blur_px = 0;
  c.classes = {{"red", 170, 10, 80, 255, 40, 255}, {"green", 45, 85, 80, 255, 40, 255}};
  return c;
}

}  // namespace

TEST(ColourSegmenter, RedHueWrapsThroughZero) {
  cv::Mat img(100, 300, CV_8UC3, bgrOfHsv(100, 150, 150));  // blue-cyan water
  cv::circle(img, {50, 50}, 30, bgrOfHsv(175, 200, 200), cv::FILLED);   // red below 180
  cv::circle(img, {150, 50}, 30, bgrOfHsv(4, 200, 200), cv::FILLED);    // red above 0
  cv::circle(img, {250, 50}, 30, bgrOfHsv(60, 200, 200), cv::FILLED);   // green
  const auto masks = colourMasks(img, redAndGreen()).classes;
  ASSERT_EQ(masks.size(), 2U);
  EXPECT_EQ(masks[0].at<std::uint8_t>(50, 50), 255);
  EXPECT_EQ(masks[0].at<std::uint8_t>(50, 150), 255);
  EXPECT_EQ(masks[0].at<std::uint8_t>(50, 250), 0);
  EXPECT_EQ(masks[1].at<std::uint8_t>(50, 250), 255);
  EXPECT_EQ(masks[1].at<std::uint8_t>(50, 50), 0);
  EXPECT_NEAR(cv::countNonZero(masks[1]), M_PI * 30 * 30, 0.05 * M_PI * 30 * 30);
}

TEST(ColourSegmenter, AnyHueIsTheWholeCircle) {
  EXPECT_TRUE(ColourClass{"learnt only"}.anyHue());  // no hue given
  EXPECT_TRUE((ColourClass{"c", 90, 89}.anyHue()));  // wrapping all the way round
  EXPECT_FALSE((ColourClass{"red", 165, 6}.anyHue()));
  EXPECT_FALSE((ColourClass{"c", 0, 178}.anyHue()));
}

// Each class's mask is exactly OpenCV's inRange of its H, S and V ranges (both halves of a wrapping hue), for
// more classes than one pass takes (8) and ranges drawn at random.
TEST(ColourSegmenter, ClassMasksAreInRangeOfEachClass) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> hue(0, 179), level(0, 255);
  cv::Mat bgr(60, 90, CV_8UC3);
  cv::randu(bgr, cv::Scalar::all(0), cv::Scalar::all(256));
  ColourMaskConfig config;
  config.blur_px = config.open_kernel_px = config.close_kernel_px = 0;
  config.saturation_floor_factor = 0;
  for (int i = 0; i < 11; ++i) {
    const int s0 = level(rng), s1 = level(rng), v0 = level(rng), v1 = level(rng);
    config.classes.push_back({"class" + std::to_string(i), hue(rng), hue(rng), std::min(s0, s1), std::max(s0, s1),
                              std::min(v0, v1), std::max(v0, v1)});
  }
  ASSERT_TRUE(config.validate().empty());
  const ColourMasks masks = colourMasks(bgr, config);
  cv::Mat hsv, any = cv::Mat::zeros(bgr.size(), CV_8UC1);
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  for (std::size_t i = 0; i < config.classes.size(); ++i) {
    const ColourClass& c = config.classes[i];
    const auto range = [&](int h0, int h1) {
      cv::Mat m;
      cv::inRange(hsv, cv::Scalar(h0, c.saturation_min, c.value_min), cv::Scalar(h1, c.saturation_max, c.value_max), m);
      return m;
    };
    const cv::Mat expected = c.hue_min <= c.hue_max ? range(c.hue_min, c.hue_max) : (range(c.hue_min, 179) | range(0, c.hue_max));
    EXPECT_EQ(cv::countNonZero(masks.classes[i] != expected), 0) << c.name;
    any |= expected;
  }
  EXPECT_EQ(cv::countNonZero(masks.any != any), 0);
}

TEST(ColourSegmenter, OpeningRemovesSpecksAndClosingFillsHolesOfTheUnion) {
  cv::Mat img(200, 200, CV_8UC3, bgrOfHsv(100, 150, 150));
  cv::rectangle(img, {20, 20, 6, 6}, bgrOfHsv(60, 200, 200), cv::FILLED);    // 6x6 speck < 10x10
  cv::rectangle(img, {80, 80, 80, 80}, bgrOfHsv(60, 200, 200), cv::FILLED);  // object...
  cv::rectangle(img, {115, 115, 5, 5}, bgrOfHsv(100, 150, 150), cv::FILLED); // ...with a small hole
  const cv::Mat green = colourMasks(img, redAndGreen()).any;
  EXPECT_EQ(cv::countNonZero(green(cv::Rect(0, 0, 60, 60))), 0);
  EXPECT_EQ(green.at<std::uint8_t>(117, 117), 255);
  EXPECT_EQ(cv::countNonZero(green), 80 * 80);

  ColourMaskConfig no_morphology = redAndGreen();
  no_morphology.open_kernel_px = 0;
  no_morphology.close_kernel_px = 0;
  const cv::Mat raw = colourMasks(img, no_morphology).any;
  EXPECT_EQ(cv::countNonZero(raw(cv::Rect(0, 0, 60, 60))), 36);
  EXPECT_EQ(raw.at<std::uint8_t>(117, 117), 0);
}

TEST(ColourSegmenter, AnObjectSpeckledBetweenTwoClassesStaysWhole) {
  cv::Mat img(200, 200, CV_8UC3, bgrOfHsv(100, 150, 150));
  cv::circle(img, {100, 100}, 60, bgrOfHsv(60, 200, 200), cv::FILLED);
  const cv::Scalar other = bgrOfHsv(40, 200, 200);
  const cv::Vec3b speck(other[0], other[1], other[2]);
  cv::RNG rng(7);
  for (int y = 100; y < 160; ++y) {  // lower half: every other pixel a hue the second class holds
    for (int x = 40; x < 160; ++x) {
      if (rng.uniform(0, 2) && cv::norm(cv::Point(x, y) - cv::Point(100, 100)) < 60) {
        img.at<cv::Vec3b>(y, x) = speck;
      }
    }
  }
  ColourMaskConfig config = redAndGreen();
  config.classes.push_back(ColourClass{"yellowgreen", 35, 45, 80, 255, 40, 255});
  const ColourMasks masks = colourMasks(img, config);
  EXPECT_NEAR(cv::countNonZero(masks.any), M_PI * 60 * 60, 0.03 * M_PI * 60 * 60);
  EXPECT_GT(cv::countNonZero(masks.classes[2]), 0.1 * M_PI * 60 * 60);
}

TEST(ColourSegmenter, BlurKeepsADimNoisyObjectWhole) {
  // A dim green disc barely above the value floor, with sensor noise: unblurred, noise breaks its mask up.
  cv::Mat img(200, 200, CV_8UC3, bgrOfHsv(100, 150, 30));
  cv::circle(img, {100, 100}, 50, bgrOfHsv(60, 200, 46), cv::FILLED);
  cv::Mat noise(img.size(), CV_16SC3);
  cv::RNG(3).fill(noise, cv::RNG::NORMAL, 0, 6);
  img.convertTo(img, CV_16SC3);
  img += noise;
  img.convertTo(img, CV_8UC3);
  const double disc = M_PI * 50 * 50;
  ColourMaskConfig config = redAndGreen();
  config.open_kernel_px = config.close_kernel_px = 0;
  const double unblurred = cv::countNonZero(colourMasks(img, config).classes[1]);
  config.blur_px = 5;
  const double blurred = cv::countNonZero(colourMasks(img, config).classes[1]);
  EXPECT_LT(unblurred, 0.9 * disc);
  EXPECT_GT(blurred, 0.95 * disc);
  EXPECT_LT(blurred, 1.03 * disc);
}

TEST(ColourSegmenter, SaturationFloorDropsInADullFrameOnly) {
  ColourMaskConfig config = redAndGreen();
  config.classes[1].saturation_min = 90;
  config.saturation_floor_factor = 4.0;
  config.saturation_floor_min = 30;
  // Murky water after white balance: nearly grey (S 8); a washed-out green object (S 45).
  cv::Mat dull(200, 200, CV_8UC3, bgrOfHsv(100, 8, 150));
  cv::circle(dull, {100, 100}, 40, bgrOfHsv(60, 45, 150), cv::FILLED);
  const ColourMasks found = colourMasks(dull, config);
  EXPECT_NEAR(found.saturation_median, 8, 2);
  EXPECT_NEAR(cv::countNonZero(found.classes[1]), M_PI * 40 * 40, 0.05 * M_PI * 40 * 40);
  // The same object in clear, colourful water (S 60 everywhere): the class's own floor holds.
  cv::Mat vivid(200, 200, CV_8UC3, bgrOfHsv(100, 60, 150));
  cv::circle(vivid, {100, 100}, 40, bgrOfHsv(60, 45, 150), cv::FILLED);
  EXPECT_EQ(cv::countNonZero(colourMasks(vivid, config).classes[1]), 0);
  config.saturation_floor_factor = 0;  // off
  EXPECT_EQ(cv::countNonZero(colourMasks(dull, config).classes[1]), 0);
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
  c.blur_px = 52;
  c.classes[1].min_contrast = -1;
  c.saturation_floor_factor = -1;
  c.saturation_floor_min = 256;
  // duplicate name, hue out of range, saturation out of range and min > max, kernel size, blur, contrast,
  // saturation floor factor and minimum
  EXPECT_EQ(c.validate().size(), 9U);
  EXPECT_FALSE(ColourMaskConfig{}.validate().empty()) << "no designated colour";
  ColourMaskConfig even = redAndGreen();
  even.blur_px = 4;  // OpenCV's Gaussian kernel is odd: refused here, not by an assertion inside OpenCV
  ASSERT_EQ(even.validate().size(), 1U);
  EXPECT_NE(even.validate()[0].find("mask.blur_px must be 0 or 1 (no blur) or odd"), std::string::npos);
}
