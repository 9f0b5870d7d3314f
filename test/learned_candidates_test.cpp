// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "underwater_stereo/detection/learned_candidates.h"

using namespace underwater_stereo;

namespace {

/// A box-sized mask with a filled disc of `radius` at `centre` (image coordinates).
cv::Mat discIn(const cv::Rect& box, const cv::Point& centre, int radius) {
  cv::Mat mask = cv::Mat::zeros(box.size(), CV_8UC1);
  cv::circle(mask, centre - box.tl(), radius, cv::Scalar(255), cv::FILLED);
  return mask;
}

}  // namespace

TEST(LearnedCandidates, RegionsAreOneObjectWhenBoxesAndPixelsOverlap) {
  // A large ring-shaped region (a shiny object's lit rim) and a small region inside its box.
  const cv::Rect ring_box(0, 0, 200, 200);
  cv::Mat ring = discIn(ring_box, {100, 100}, 100);
  cv::circle(ring, {100, 100}, 60, cv::Scalar(0), cv::FILLED);
  const cv::Rect small_box(80, 80, 40, 40);
  // In its box but on none of its pixels: another object (in front of the ring's hole).
  EXPECT_FALSE(sameRegion(ring_box, ring, small_box, discIn(small_box, {100, 100}, 20), 0.3));
  // On its pixels: another view of the same object, whichever comes first.
  const cv::Rect on_rim(160, 80, 40, 40);
  EXPECT_TRUE(sameRegion(ring_box, ring, on_rim, discIn(on_rim, {180, 100}, 20), 0.3));
  EXPECT_TRUE(sameRegion(on_rim, discIn(on_rim, {180, 100}, 20), ring_box, ring, 0.3));
  // Boxes that barely touch are never one object, whatever their masks.
  const cv::Rect beside(190, 0, 100, 100);
  EXPECT_FALSE(sameRegion(ring_box, ring, beside, cv::Mat(beside.size(), CV_8UC1, cv::Scalar(255)), 0.3));
  EXPECT_DOUBLE_EQ(overlapOfSmaller(ring_box, small_box), 1.0);
}
