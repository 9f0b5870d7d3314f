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

/// Masks as colourMasks() gives them, from per-class masks already clean.
ColourMasks masksOf(const std::vector<cv::Mat>& classes) {
  ColourMasks m;
  m.classes = classes;
  m.any = cv::Mat::zeros(classes.at(0).size(), CV_8UC1);
  for (const cv::Mat& c : classes) m.any |= c;
  return m;
}

const ColourClass kRed{"red", 165, 8}, kOrange{"orange", 9, 16}, kYellow{"yellow", 17, 25}, kGreen{"green", 26, 45};

}  // namespace

TEST(CandidateFinder, ClassifiesOutlines) {
  EXPECT_EQ(classifyOutline(drawn([](cv::Mat& m) { cv::circle(m, {200, 200}, 80, 255, cv::FILLED); })), OutlineKind::kCircle);
  EXPECT_EQ(classifyOutline(drawn([](cv::Mat& m) { cv::ellipse(m, {200, 200}, {120, 50}, 30, 0, 360, 255, cv::FILLED); })),
            OutlineKind::kEllipse);
  EXPECT_EQ(classifyOutline(drawn([](cv::Mat& m) {
              std::vector<cv::Point> t{{200, 40}, {360, 330}, {40, 330}};
              cv::fillConvexPoly(m, t, 255);
            })),
            OutlineKind::kTriangle);
  EXPECT_EQ(classifyOutline(drawn([](cv::Mat& m) {
              cv::RotatedRect r({200, 200}, {240, 90}, 25);
              cv::Point2f pts[4];
              r.points(pts);
              std::vector<cv::Point> poly(pts, pts + 4);
              cv::fillConvexPoly(m, poly, 255);
            })),
            OutlineKind::kRectangle);
  EXPECT_EQ(classifyOutline(drawn([](cv::Mat& m) {
              std::vector<cv::Point> star;
              for (int i = 0; i < 10; ++i) {
                const double r = i % 2 ? 60 : 150, a = i * M_PI / 5;
                star.emplace_back(200 + r * std::cos(a), 200 + r * std::sin(a));
              }
              cv::fillPoly(m, std::vector<std::vector<cv::Point>>{star}, 255);
            })),
            OutlineKind::kPolygon);
  EXPECT_THROW(classifyOutline({{0, 0}, {1, 1}}), std::invalid_argument);
}

TEST(CandidateFinder, FindsColouredRegionsLargestFirstAndDropsSmallOnes) {
  cv::Mat img(300, 400, CV_8UC3, cv::Scalar(120, 110, 60));
  cv::Mat red = cv::Mat::zeros(img.size(), CV_8UC1), green = red.clone();
  cv::circle(red, {100, 150}, 40, 255, cv::FILLED);
  cv::rectangle(green, cv::Rect(250, 100, 100, 60), 255, cv::FILLED);
  cv::circle(green, {50, 40}, 8, 255, cv::FILLED);  // ~200 px < min_area_px
  img.setTo(cv::Scalar(30, 30, 200), red);
  const std::vector<Candidate> found = findCandidates(img, masksOf({red, green}), {kRed, kGreen}, CandidateConfig{});
  ASSERT_EQ(found.size(), 2U);
  EXPECT_EQ(found[0].colour_index, 1);
  EXPECT_EQ(found[0].outline, OutlineKind::kRectangle);
  EXPECT_EQ(found[0].roi, cv::Rect(250, 100, 100, 60));
  EXPECT_EQ(found[1].colour_index, 0);
  EXPECT_EQ(found[1].outline, OutlineKind::kCircle);
  EXPECT_NEAR(found[1].area_px, M_PI * 40 * 40, 0.03 * M_PI * 40 * 40);
  EXPECT_DOUBLE_EQ(found[1].colour_fraction, 1.0);
  EXPECT_NEAR(found[1].mean_bgr[2], 200, 1);
  EXPECT_EQ(found[1].mask.size(), found[1].roi.size());
}

TEST(CandidateFinder, HueNeighboursTouchThroughZero) {
  EXPECT_TRUE(hueNeighbours(kRed, kOrange));
  EXPECT_TRUE(hueNeighbours(kOrange, kRed));
  EXPECT_TRUE(hueNeighbours(kYellow, kGreen));
  EXPECT_FALSE(hueNeighbours(kRed, kGreen));
  EXPECT_FALSE(hueNeighbours(kOrange, kGreen));
  EXPECT_TRUE(hueNeighbours(ColourClass{"magenta", 150, 164}, kRed));
  EXPECT_FALSE(hueNeighbours(ColourClass{"blue", 100, 130}, kRed));
  EXPECT_TRUE(hueNeighbours(ColourClass{"wide", 10, 40}, ColourClass{"inside", 20, 30}));  // one inside the other
  EXPECT_TRUE(hueNeighbours(ColourClass{"inside", 20, 30}, ColourClass{"wide", 10, 40}));
  EXPECT_FALSE(hueNeighbours(kRed, kYellow));  // orange between them
}

TEST(CandidateFinder, ShadedBallAcrossTwoNeighbourClassesIsOneObjectOfItsMajorityColour) {
  // A yellow ball whose lower third reads orange, and beside it a red and a green ball that overlap.
  cv::Mat img(300, 500, CV_8UC3, cv::Scalar(120, 110, 60));
  cv::Mat masks[4] = {cv::Mat::zeros(img.size(), CV_8UC1), cv::Mat::zeros(img.size(), CV_8UC1),
                      cv::Mat::zeros(img.size(), CV_8UC1), cv::Mat::zeros(img.size(), CV_8UC1)};
  cv::circle(masks[2], {100, 150}, 60, 255, cv::FILLED);
  masks[2](cv::Rect(0, 190, 500, 110)).copyTo(masks[1](cv::Rect(0, 190, 500, 110)));
  masks[2](cv::Rect(0, 190, 500, 110)).setTo(0);
  cv::circle(masks[0], {300, 150}, 50, 255, cv::FILLED);
  cv::circle(masks[3], {390, 150}, 50, 255, cv::FILLED);
  masks[3].setTo(0, masks[0]);
  const std::vector<Candidate> found =
      findCandidates(img, masksOf({masks[0], masks[1], masks[2], masks[3]}), {kRed, kOrange, kYellow, kGreen}, CandidateConfig{});
  ASSERT_EQ(found.size(), 3U);
  EXPECT_EQ(found[0].colour_index, 2);  // yellow: the whole ball, orange third included
  EXPECT_EQ(found[0].roi, cv::Rect(40, 90, 121, 121));
  EXPECT_EQ(found[0].outline, OutlineKind::kCircle);
  EXPECT_DOUBLE_EQ(found[0].colour_fraction, 1.0);
  EXPECT_EQ(found[1].colour_index, 0);  // red, whole
  EXPECT_EQ(found[1].roi.tl(), cv::Point(250, 100));
  EXPECT_NEAR(found[1].roi.width, 101, 1);  // the last column where the balls touch may go either way
  EXPECT_EQ(found[1].roi.height, 101);
  EXPECT_EQ(found[2].colour_index, 3);  // green, the part the red ball leaves
  EXPECT_GT(found[2].roi.x, 340);  // without the pixels the red ball covers
  EXPECT_EQ(found[2].roi.x + found[2].roi.width, 441);
}

TEST(CandidateFinder, MinContrastDropsADarkObjectThatOnlyLooksRed) {
  cv::Mat img(300, 400, CV_8UC3, cv::Scalar(120, 120, 120));  // water after white balance
  cv::circle(img, {100, 150}, 40, cv::Scalar(40, 40, 180), cv::FILLED);  // red buoy, brighter than water
  cv::circle(img, {300, 150}, 40, cv::Scalar(50, 50, 95), cv::FILLED);   // black weight, reddish, darker
  cv::Mat red = cv::Mat::zeros(img.size(), CV_8UC1);
  cv::circle(red, {100, 150}, 40, 255, cv::FILLED);
  cv::circle(red, {300, 150}, 40, 255, cv::FILLED);
  ColourClass strict = kRed;
  strict.min_contrast = 1.1;
  EXPECT_EQ(findCandidates(img, masksOf({red}), {kRed}, CandidateConfig{}).size(), 2U);
  const std::vector<Candidate> found = findCandidates(img, masksOf({red}), {strict}, CandidateConfig{});
  ASSERT_EQ(found.size(), 1U);
  EXPECT_EQ(found[0].roi.x, 60);
}

TEST(CandidateFinder, FaceContrastIsHighForFlatFacesOfDifferentShadingOnly) {
  cv::Mat img(300, 600, CV_8UC3, cv::Scalar(120, 120, 120));
  cv::rectangle(img, cv::Rect(30, 100, 60, 100), cv::Scalar(30, 160, 30), cv::FILLED);   // box: lit face
  cv::rectangle(img, cv::Rect(90, 100, 80, 100), cv::Scalar(20, 100, 20), cv::FILLED);   // ...shaded face
  for (int r = 60; r > 0; --r) {  // sphere: brightness falls smoothly from the centre
    cv::circle(img, {300, 150}, r, cv::Scalar(20, 60 + 2 * (60 - r), 20), cv::FILLED);
  }
  cv::rectangle(img, cv::Rect(420, 100, 140, 100), cv::Scalar(30, 140, 30), cv::FILLED);  // panel: one level
  cv::Mat noise(img.size(), CV_16SC3);
  cv::RNG(5).fill(noise, cv::RNG::NORMAL, 0, 3);
  img.convertTo(img, CV_16SC3);
  img += noise;
  img.convertTo(img, CV_8UC3);
  cv::Mat green = cv::Mat::zeros(img.size(), CV_8UC1);
  cv::rectangle(green, cv::Rect(30, 100, 140, 100), 255, cv::FILLED);
  cv::circle(green, {300, 150}, 60, 255, cv::FILLED);
  cv::rectangle(green, cv::Rect(420, 100, 140, 100), 255, cv::FILLED);
  std::vector<Candidate> found = findCandidates(img, masksOf({green}), {kGreen}, CandidateConfig{});
  ASSERT_EQ(found.size(), 3U);
  std::sort(found.begin(), found.end(), [](const Candidate& a, const Candidate& b) { return a.roi.x < b.roi.x; });
  EXPECT_GT(found[0].face_contrast, 40.0) << "box";
  EXPECT_LT(found[1].face_contrast, 12.0) << "sphere";
  EXPECT_LT(found[2].face_contrast, 12.0) << "panel";
}

TEST(CandidateFinder, GreyThresholdModeKeepsOnlyContoursThatCarryTheColour) {
  cv::Mat img(300, 400, CV_8UC3, cv::Scalar(200, 200, 200));  // bright water
  cv::circle(img, {100, 150}, 40, cv::Scalar(30, 30, 120), cv::FILLED);  // dark red object
  cv::circle(img, {300, 150}, 40, cv::Scalar(40, 40, 40), cv::FILLED);   // dark grey rock
  cv::Mat red = cv::Mat::zeros(img.size(), CV_8UC1);
  cv::circle(red, {100, 150}, 38, 255, cv::FILLED);
  CandidateConfig config;
  config.source = ContourSource::kGreyThreshold;
  const std::vector<Candidate> found = findCandidates(img, masksOf({red}), {kRed}, config);
  ASSERT_EQ(found.size(), 1U);
  EXPECT_LT(std::abs(found[0].roi.x + found[0].roi.width / 2 - 100), 2);
  EXPECT_GT(found[0].colour_fraction, 0.85);
}

TEST(CandidateFinder, GarbageInputThrowsAndNothingFoundIsEmpty) {
  const cv::Mat img(100, 100, CV_8UC3, cv::Scalar(0));
  EXPECT_TRUE(findCandidates(img, masksOf({cv::Mat::zeros(100, 100, CV_8UC1)}), {kRed}, CandidateConfig{}).empty());
  EXPECT_THROW(findCandidates(img, masksOf({cv::Mat::zeros(50, 100, CV_8UC1)}), {kRed}, CandidateConfig{}),
               std::invalid_argument);
  EXPECT_THROW(findCandidates(cv::Mat(), ColourMasks{}, {}, CandidateConfig{}), std::invalid_argument);
  ColourMasks wrong_type;
  wrong_type.classes = {cv::Mat::zeros(100, 100, CV_16UC1)};
  wrong_type.any = cv::Mat::zeros(100, 100, CV_8UC1);
  EXPECT_THROW(findCandidates(img, wrong_type, {kRed}, CandidateConfig{}), std::invalid_argument);
  EXPECT_THROW(findCandidates(img, masksOf({cv::Mat::zeros(100, 100, CV_8UC1)}), {kRed, kGreen}, CandidateConfig{}),
               std::invalid_argument);
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
