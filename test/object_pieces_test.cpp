// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "underwater_stereo/detection/object_pieces.h"

namespace underwater_stereo {
namespace {

/// Points on a flat patch of `side` m at depth z, from x0, every 1 cm.
std::vector<Eigen::Vector3f> patch(float x0, float z, float side) {
  std::vector<Eigen::Vector3f> p;
  for (float x = 0; x <= side; x += 0.01f) {
    for (float y = 0; y <= side; y += 0.01f) p.emplace_back(x0 + x, y, z);
  }
  return p;
}

TEST(ObjectPieces, JoinsTouchingClustersThatMayJoinOnly) {
  // Pieces 0 and 1 of one red object 5 cm apart; 2 red 1 m further; 3 green touching 1; 4 red touching 0.
  const std::vector<std::vector<Eigen::Vector3f>> clusters{patch(0, 1, 0.2f), patch(0.25f, 1, 0.2f), patch(0, 2, 0.2f),
                                                           patch(0.46f, 1, 0.2f), patch(-0.25f, 1, 0.2f)};
  const std::vector<int> colours{0, 0, 0, 1, 0};
  const auto one_colour = [&](int i, int j) { return colours[i] == colours[j]; };
  EXPECT_EQ(piecesOfOneObject(one_colour, clusters, 0.06), (std::vector<std::vector<int>>{{0, 1, 4}}));
  // Narrower than the gaps: nothing joined.
  EXPECT_TRUE(piecesOfOneObject(one_colour, clusters, 0.04).empty());
  // Joined through a member: 4 touches 0, 0 touches 1.
  const auto any = [](int, int) { return true; };
  EXPECT_EQ(piecesOfOneObject(any, {clusters[4], clusters[1], clusters[0]}, 0.06),
            (std::vector<std::vector<int>>{{0, 1, 2}}));
  // Green joins too where allowed: 3 touches 1.
  EXPECT_EQ(piecesOfOneObject(any, clusters, 0.06), (std::vector<std::vector<int>>{{0, 1, 3, 4}}));
}

TEST(ObjectPieces, RefusesBadInput) {
  const auto any = [](int, int) { return true; };
  EXPECT_THROW(piecesOfOneObject(any, {patch(0, 1, 0.1f)}, 0.0), std::invalid_argument);
  EXPECT_TRUE(piecesOfOneObject(any, {{}, patch(0, 1, 0.1f)}, 0.1).empty());
  EXPECT_THROW(joinedCandidate({}, cv::Size(100, 100)), std::invalid_argument);
  Candidate a, b;
  a.colour_index = 0;
  b.colour_index = 1;
  EXPECT_THROW(joinedCandidate({&a, &b}, cv::Size(100, 100)), std::invalid_argument);
}

Candidate disc(const cv::Point& centre, int radius, double fraction, const cv::Scalar& bgr) {
  Candidate c;
  c.colour_index = 2;
  c.roi = cv::Rect(centre.x - radius, centre.y - radius, 2 * radius + 1, 2 * radius + 1);
  c.mask = cv::Mat::zeros(c.roi.size(), CV_8UC1);
  cv::circle(c.mask, cv::Point(radius, radius), radius, 255, cv::FILLED);
  c.area_px = cv::countNonZero(c.mask);
  c.colour_fraction = fraction;
  c.mean_bgr = bgr;
  c.face_contrast = radius;
  return c;
}

TEST(ObjectPieces, JoinedRegionIsTheUnionOfThePieces) {
  // Two halves of one disc of radius 40 at (100, 100), split by a 4-px band.
  Candidate whole = disc(cv::Point(100, 100), 40, 1, cv::Scalar());
  Candidate top = whole, bottom = whole;
  top.mask = whole.mask.clone();
  bottom.mask = whole.mask.clone();
  top.mask(cv::Rect(0, 39, whole.roi.width, whole.roi.height - 39)).setTo(0);
  bottom.mask(cv::Rect(0, 0, whole.roi.width, 43)).setTo(0);
  top.area_px = cv::countNonZero(top.mask);
  bottom.area_px = cv::countNonZero(bottom.mask);
  top.colour_fraction = 0.9;
  bottom.colour_fraction = 0.7;
  top.mean_bgr = cv::Scalar(0, 0, 200);
  bottom.mean_bgr = cv::Scalar(0, 0, 100);
  top.face_contrast = 3;
  bottom.face_contrast = 30;
  bottom.area_px = top.area_px + 1;  // the larger piece
  const Candidate joined = joinedCandidate({&bottom, &top}, cv::Size(640, 480));
  EXPECT_EQ(joined.colour_index, 2);
  EXPECT_EQ(joined.roi, whole.roi);
  EXPECT_EQ(cv::countNonZero(joined.mask), cv::countNonZero(top.mask) + cv::countNonZero(bottom.mask));
  EXPECT_DOUBLE_EQ(joined.area_px, top.area_px + bottom.area_px);
  EXPECT_DOUBLE_EQ(joined.colour_fraction, 0.9);  // the most confident piece's
  EXPECT_DOUBLE_EQ(joined.face_contrast, 30);     // the largest piece's
  const double w = bottom.area_px / joined.area_px;
  EXPECT_NEAR(joined.mean_bgr[2], 100 * w + 200 * (1 - w), 1e-9);
  // The contour is the larger half's (the union is not connected across the band): the top one, rows 0-38 of
  // the disc against 43-80, in image pixels.
  ASSERT_GE(joined.contour.size(), 3u);
  EXPECT_EQ(cv::boundingRect(joined.contour), cv::Rect(whole.roi.x + 1, whole.roi.y, whole.roi.width - 2, 39));
  // Pieces reaching past the frame are cut to it.
  Candidate edge = disc(cv::Point(630, 470), 20, 0.8, cv::Scalar());
  edge.roi &= cv::Rect(0, 0, 640, 480);
  edge.mask = edge.mask(cv::Rect(0, 0, edge.roi.width, edge.roi.height)).clone();
  const Candidate cut = joinedCandidate({&edge}, cv::Size(640, 480));
  EXPECT_EQ(cut.roi, cv::Rect(610, 450, 30, 30));
}

// The region pieces stood in place of is theirs only when the group is exactly the candidates that stood in its place.
TEST(ObjectPieces, TheRegionOfPiecesIsTheOneTheyAllAndOnlyTheyStoodFor) {
  const std::vector<int> whole_of{-1, 0, 0, 1, 0};
  EXPECT_EQ(regionOfPieces({1, 2, 4}, whole_of), 0);
  EXPECT_EQ(regionOfPieces({1, 2}, whole_of), -1);        // one of its pieces is not in the group (another object?)
  EXPECT_EQ(regionOfPieces({1, 2, 3, 4}, whole_of), -1);  // the group holds a piece of another region
  EXPECT_EQ(regionOfPieces({0, 3}, whole_of), -1);        // the first stood for none
  EXPECT_EQ(regionOfPieces({3}, whole_of), 1);
  EXPECT_EQ(regionOfPieces({}, whole_of), -1);
  EXPECT_THROW(regionOfPieces({1, 2, 4}, {}), std::invalid_argument) << "whole_of must cover the group";
  EXPECT_THROW(regionOfPieces({1, 5}, whole_of), std::invalid_argument);
  EXPECT_THROW(regionOfPieces({-1}, whole_of), std::invalid_argument);
}

// The share of a region's pixels its pieces cover counts pixels both hold (soft edges from 128 on), not areas alone.
TEST(ObjectPieces, PiecesCoverTheShareOfTheirRegionsPixelsTheyHold) {
  const Candidate region = disc(cv::Point(100, 100), 40, 0.8, cv::Scalar());
  EXPECT_NEAR(shareCovered(region, region), 1.0, 1e-12);
  // The top half (rows above the centre) covers about half.
  Candidate top = region;
  top.mask = region.mask.clone();
  top.mask(cv::Rect(0, 40, top.roi.width, top.roi.height - 40)).setTo(0);
  EXPECT_NEAR(shareCovered(top, region), 0.5, 0.03);
  // As large as the region but beside it: covers nothing, though its area is the region's.
  Candidate beside = disc(cv::Point(300, 100), 40, 0.8, cv::Scalar());
  EXPECT_DOUBLE_EQ(shareCovered(beside, region), 0.0);
  // Faint edge pixels (under 128) count for neither.
  Candidate faint = region;
  faint.mask = region.mask / 4;
  EXPECT_DOUBLE_EQ(shareCovered(faint, region), 0.0);
  EXPECT_DOUBLE_EQ(shareCovered(region, faint), 0.0) << "a region without pixels is covered by nothing";
}

}  // namespace
}  // namespace underwater_stereo
