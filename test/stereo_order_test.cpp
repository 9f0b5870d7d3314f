// SPDX-License-Identifier: BSD-3-Clause
// Whether a pair came with its left and right images swapped (stereo_order.h).
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/stereo_order.h"

using namespace underwater_stereo;

namespace {

/// A grey frame of flat water with a shaded disc of radius 30 px centred at column `x`, row `y`.
cv::Mat discAt(int x, int y = 100) {
  cv::Mat frame(200, 400, CV_8UC1, cv::Scalar(60));
  for (int r = 30; r > 0; r -= 3) cv::circle(frame, {x, y}, r, cv::Scalar(200 - 4 * r), cv::FILLED, cv::LINE_AA);
  return frame;
}

const cv::Rect kDiscInLeft(200 - 32, 100 - 32, 64, 64);  // around the disc at column 200

}  // namespace

TEST(StereoOrder, AnObjectsRightViewLeftOfItsLeftOneIsInOrder) {
  const cv::Mat left = discAt(200), right = discAt(160);  // disparity 40
  const StereoOrder o = compareStereoOrder(left, right, kDiscInLeft, 10, 100, 0.0);
  EXPECT_GT(o.forward, 0.9);
  EXPECT_LT(o.backward, 0.5);
  EXPECT_FALSE(o.looksSwapped());
}

TEST(StereoOrder, TheSamePairSwappedLooksSwapped) {
  const cv::Mat left = discAt(200), right = discAt(160);
  const StereoOrder o = compareStereoOrder(right, left, cv::Rect(160 - 32, 100 - 32, 64, 64), 10, 100, 0.0);
  EXPECT_GT(o.backward, 0.9);
  EXPECT_TRUE(o.looksSwapped());
}

TEST(StereoOrder, TheRightCamerasRowOffsetIsLookedForOnEachSide) {
  // The right camera shows everything 12 rows lower (a slight tilt between the cameras): a swapped pair 12 higher.
  const cv::Mat left = discAt(200), right = discAt(160, 112);
  EXPECT_GT(compareStereoOrder(left, right, kDiscInLeft, 10, 100, 12.0).forward, 0.9);
  const StereoOrder swapped = compareStereoOrder(right, left, cv::Rect(160 - 32, 112 - 32, 64, 64), 10, 100, 12.0);
  EXPECT_GT(swapped.backward, 0.9);
  EXPECT_TRUE(swapped.looksSwapped());
  EXPECT_THROW(compareStereoOrder(left, right, kDiscInLeft, 10, 100, std::nan("")), std::invalid_argument);
  // A disc cut by the bottom border: the rows the right image cannot show 12 rows lower are left out on both sides.
  const cv::Mat low_left = discAt(200, 185), low_right = discAt(160, 197);
  const cv::Rect low(200 - 32, 185 - 32, 64, 200 - (185 - 32));
  const StereoOrder in_order = compareStereoOrder(low_left, low_right, low, 10, 100, 12.0);
  EXPECT_GT(in_order.forward, 0.9);
  EXPECT_FALSE(in_order.looksSwapped());
  const StereoOrder low_swapped = compareStereoOrder(low_right, low_left, cv::Rect(160 - 32, 197 - 32, 64, 200 - (197 - 32)),
                                                     10, 100, 12.0);
  EXPECT_NE(low_swapped.forward, StereoOrder::kNotCompared);
  EXPECT_TRUE(low_swapped.looksSwapped());
  // And one cut by the top border, swapped: its view lies 12 rows higher, the rows above them are left out.
  const StereoOrder high_swapped = compareStereoOrder(discAt(160, 27), discAt(200, 15), cv::Rect(128, 0, 64, 59), 10, 100, 12.0);
  EXPECT_NE(high_swapped.forward, StereoOrder::kNotCompared);
  EXPECT_TRUE(high_swapped.looksSwapped());
}

TEST(StereoOrder, AFlatPatchAViewBeyondTheImageOrAThinRegionSaysNothing) {
  const cv::Mat flat(200, 400, CV_8UC1, cv::Scalar(60));
  const StereoOrder o = compareStereoOrder(flat, flat, kDiscInLeft, 10, 100, 0.0);
  EXPECT_FALSE(o.looksSwapped());
  // Disparities under the workspace's smallest are not compared: an object at infinity (disparity 0) is no view.
  const StereoOrder far = compareStereoOrder(discAt(200), discAt(200), kDiscInLeft, 10, 100, 0.0);
  EXPECT_FALSE(far.looksSwapped());
  EXPECT_LT(far.forward, 0.9);
  // A region too thin to keep 4 pixels across when scaled to the compared size is not compared.
  const StereoOrder thin = compareStereoOrder(discAt(200), discAt(160), cv::Rect(0, 100, 400, 3), 10, 100, 0.0);
  EXPECT_EQ(thin.forward, StereoOrder::kNotCompared);
  EXPECT_EQ(thin.backward, StereoOrder::kNotCompared);
}

// An object at the left border: in a pair in order its right view lies beyond the right image, so its forward side is
// not compared, and a smooth patch that matches itself a little shifted (backward) must not take the pair for swapped;
// its backward match is weighed against the patch's match with its own image there instead.
TEST(StereoOrder, AnObjectAtTheLeftBorderIsWeighedAgainstItsOwnImage) {
  cv::Mat left(200, 400, CV_8UC1, cv::Scalar(140)), right = left.clone();
  for (int y = 20; y < 180; ++y) {  // a large plain box cut by the left border, shaded top to bottom; disparity 40
    left(cv::Rect(0, y, 240, 1)).setTo(40 + y);
    right(cv::Rect(0, y, 200, 1)).setTo(40 + y);
  }
  const StereoOrder o = compareStereoOrder(left, right, cv::Rect(0, 20, 240, 160), 10, 100, 0.0);
  EXPECT_EQ(o.forward, StereoOrder::kNotCompared);
  EXPECT_GT(o.backward, 0.8) << "the case this guards: the shifted patch matches itself";
  EXPECT_GT(o.backward_in_left, 0.8) << "...as well in its own image";
  EXPECT_FALSE(o.looksSwapped());
  EXPECT_FALSE(pairOrder({ObjectOrderEvidence{false, o}}).looksSwapped());
  // A shaded disc at the left border of a swapped pair: its view lies right of it, where its own image has water.
  const StereoOrder disc = compareStereoOrder(discAt(20), discAt(60), cv::Rect(0, 100 - 32, 52, 64), 20, 100, 0.0);
  EXPECT_EQ(disc.forward, StereoOrder::kNotCompared);
  EXPECT_GT(disc.backward, 0.9);
  EXPECT_LT(disc.backward_in_left, 0.7);
  EXPECT_TRUE(disc.looksSwapped());
  // A large textured object at the left border of a swapped pair, the smallest shift a few compared pixels: its own
  // image is searched from that shift on, not from the slack before it (where any patch matches itself).
  cv::Mat texture(400, 900, CV_8UC1);
  cv::RNG(7).fill(texture, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(texture, texture, cv::Size(0, 0), 8);
  cv::normalize(texture, texture, 20, 230, cv::NORM_MINMAX);
  cv::Mat real_right(texture.size(), CV_8UC1, cv::Scalar(130));
  texture(cv::Rect(60, 0, 840, 400)).copyTo(real_right(cv::Rect(0, 0, 840, 400)));  // disparity 60
  const cv::Rect at_border(0, 50, 700, 300);  // in the real right image, given as the left
  const int slack = static_cast<int>(std::ceil(700 / 64.0));  // one compared pixel
  const StereoOrder textured = compareStereoOrder(real_right, texture, at_border, slack + 3, 100, 0.0);
  EXPECT_EQ(textured.forward, StereoOrder::kNotCompared);
  EXPECT_GT(textured.backward, 0.9);
  EXPECT_LT(textured.backward_in_left, 0.7);
  EXPECT_TRUE(textured.looksSwapped());
}

TEST(StereoOrder, RefusesFramesOfOtherSizesAndARegionOutsideThem) {
  EXPECT_THROW(compareStereoOrder(discAt(200), cv::Mat(100, 100, CV_8UC1, cv::Scalar(0)), kDiscInLeft, 10, 100, 0.0),
               std::invalid_argument);
  EXPECT_THROW(compareStereoOrder(discAt(200), discAt(160), cv::Rect(380, 0, 64, 64), 10, 100, 0.0), std::invalid_argument);
}

TEST(StereoOrder, APairLooksSwappedWhenHalfItsObjectsDoAndNoFewerFoundTheirSilhouette) {
  const ObjectOrderEvidence swapped{false, {0.2, 0.95}}, unsure{false, {0.5, 0.6}}, in_order{false, {0.9, 0.3}};
  ObjectOrderEvidence with_silhouette;
  with_silhouette.silhouette = true;
  EXPECT_FALSE(pairOrder({}).looksSwapped());
  EXPECT_TRUE(pairOrder({swapped}).looksSwapped());
  EXPECT_TRUE(pairOrder({swapped, unsure}).looksSwapped());
  EXPECT_FALSE(pairOrder({swapped, unsure, in_order}).looksSwapped());
  EXPECT_FALSE(pairOrder({unsure}).looksSwapped());
  EXPECT_TRUE(pairOrder({swapped, with_silhouette}).looksSwapped());
  EXPECT_TRUE(pairOrder({swapped, swapped, with_silhouette}).looksSwapped());
  EXPECT_FALSE(pairOrder({swapped, with_silhouette, with_silhouette}).looksSwapped());
}

// One pair now and then that looks swapped is published; the third with no pair of objects between them points at the
// wiring; pairs without objects that look in order neither count nor reset.
TEST(StereoOrder, SwappedPairsWithoutObjectsBetweenThemPointAtTheWiring) {
  SwappedPairWatch watch;
  EXPECT_EQ(watch.add(true, false), 0);
  EXPECT_EQ(watch.add(false, true), 0);  // objects: the count starts again
  EXPECT_EQ(watch.add(true, false), 0);
  EXPECT_EQ(watch.add(false, false), 0);  // an empty pair in order: neither
  EXPECT_EQ(watch.add(true, false), 0);
  EXPECT_EQ(watch.add(true, false), SwappedPairWatch::kPairsForWiring);
  EXPECT_EQ(watch.add(true, false), SwappedPairWatch::kPairsForWiring + 1);
  EXPECT_EQ(watch.add(false, true), 0);
  EXPECT_EQ(watch.add(true, false), 0);
}
