// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "underwater_stereo/detection/candidate_finder.h"

using namespace underwater_stereo;

namespace {

std::vector<cv::Point> drawn(const std::function<void(cv::Mat&)>& draw) {
  cv::Mat m = cv::Mat::zeros(400, 400, CV_8UC1);
  draw(m);
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(m, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  return contours.at(0);
}

}  // namespace

TEST(CandidateFinder, ClassifiesOutlines) {
  EXPECT_EQ(classifyOutline(drawn([](cv::Mat& m) { cv::circle(m, {200, 200}, 80, 255, cv::FILLED); })), "circle");
  EXPECT_EQ(classifyOutline(drawn([](cv::Mat& m) { cv::ellipse(m, {200, 200}, {120, 50}, 30, 0, 360, 255, cv::FILLED); })),
            "ellipse");
  EXPECT_EQ(classifyOutline(drawn([](cv::Mat& m) {
              std::vector<cv::Point> t{{200, 40}, {360, 330}, {40, 330}};
              cv::fillConvexPoly(m, t, 255);
            })),
            "triangle");
  EXPECT_EQ(classifyOutline(drawn([](cv::Mat& m) {
              cv::RotatedRect r({200, 200}, {240, 90}, 25);
              cv::Point2f pts[4];
              r.points(pts);
              std::vector<cv::Point> poly(pts, pts + 4);
              cv::fillConvexPoly(m, poly, 255);
            })),
            "rectangle");
  EXPECT_EQ(classifyOutline(drawn([](cv::Mat& m) {
              std::vector<cv::Point> star;
              for (int i = 0; i < 10; ++i) {
                const double r = i % 2 ? 60 : 150, a = i * M_PI / 5;
                star.emplace_back(200 + r * std::cos(a), 200 + r * std::sin(a));
              }
              cv::fillPoly(m, std::vector<std::vector<cv::Point>>{star}, 255);
            })),
            "polygon");
  EXPECT_THROW(classifyOutline({{0, 0}, {1, 1}}), std::invalid_argument);
}

TEST(CandidateFinder, FindsColouredRegionsLargestFirstAndDropsSmallOnes) {
  cv::Mat img(300, 400, CV_8UC3, cv::Scalar(120, 110, 60));
  cv::Mat red = cv::Mat::zeros(img.size(), CV_8UC1), green = red.clone();
  cv::circle(red, {100, 150}, 40, 255, cv::FILLED);
  cv::rectangle(green, cv::Rect(250, 100, 100, 60), 255, cv::FILLED);
  cv::circle(green, {50, 40}, 8, 255, cv::FILLED);  // ~200 px < min_area_px
  img.setTo(cv::Scalar(30, 30, 200), red);
  const std::vector<Candidate> found = findCandidates(img, {red, green}, CandidateConfig{});
  ASSERT_EQ(found.size(), 2U);
  EXPECT_EQ(found[0].colour_index, 1);
  EXPECT_EQ(found[0].outline, "rectangle");
  EXPECT_EQ(found[0].roi, cv::Rect(250, 100, 100, 60));
  EXPECT_EQ(found[1].colour_index, 0);
  EXPECT_EQ(found[1].outline, "circle");
  EXPECT_NEAR(found[1].area_px, M_PI * 40 * 40, 0.03 * M_PI * 40 * 40);
  EXPECT_DOUBLE_EQ(found[1].colour_fraction, 1.0);
  EXPECT_NEAR(found[1].mean_bgr[2], 200, 1);
  EXPECT_EQ(found[1].mask.size(), found[1].roi.size());
}

TEST(CandidateFinder, GreyThresholdModeKeepsOnlyContoursThatCarryTheColour) {
  cv::Mat img(300, 400, CV_8UC3, cv::Scalar(200, 200, 200));  // bright water
  cv::circle(img, {100, 150}, 40, cv::Scalar(30, 30, 120), cv::FILLED);  // dark red object
  cv::circle(img, {300, 150}, 40, cv::Scalar(40, 40, 40), cv::FILLED);   // dark grey rock
  cv::Mat red = cv::Mat::zeros(img.size(), CV_8UC1);
  cv::circle(red, {100, 150}, 38, 255, cv::FILLED);
  CandidateConfig config;
  config.source = ContourSource::kGreyThreshold;
  const std::vector<Candidate> found = findCandidates(img, {red}, config);
  ASSERT_EQ(found.size(), 1U);
  EXPECT_LT(std::abs(found[0].roi.x + found[0].roi.width / 2 - 100), 2);
  EXPECT_GT(found[0].colour_fraction, 0.85);
}

TEST(CandidateFinder, GarbageInputThrowsAndNothingFoundIsEmpty) {
  const cv::Mat img(100, 100, CV_8UC3, cv::Scalar(0));
  EXPECT_TRUE(findCandidates(img, {cv::Mat::zeros(100, 100, CV_8UC1)}, CandidateConfig{}).empty());
  EXPECT_THROW(findCandidates(img, {cv::Mat::zeros(50, 100, CV_8UC1)}, CandidateConfig{}), std::invalid_argument);
  EXPECT_THROW(findCandidates(cv::Mat(), {}, CandidateConfig{}), std::invalid_argument);
  EXPECT_THROW(findCandidates(img, {cv::Mat::zeros(100, 100, CV_16UC1)}, CandidateConfig{}), std::invalid_argument);
}

TEST(CandidateFinder, InvalidConfigListsEveryProblem) {
  CandidateConfig c;
  EXPECT_TRUE(c.validate().empty());
  c.blur_kernel_px = 4;
  c.min_area_px = 0;
  c.min_colour_fraction = 0;
  c.max_candidates = 0;
  c.fixed_threshold = 300;
  EXPECT_EQ(c.validate().size(), 5U);
}
