// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include "underwater_stereo/sim/stereo_rig.h"

using namespace underwater_stereo::sim;

TEST(StereoRig, DefaultsMatchTheRealHeadInWater) {
  const StereoRig rig{RigConfig{}};
  // 8 mm / 5.86 um = 1365 px in air; the flat port in water multiplies by ~1.333.
  EXPECT_NEAR(rig.left().K(0, 0), 1820.0, 1.0);
  EXPECT_EQ(rig.left().width, 1920);
  EXPECT_EQ(rig.left().height, 1200);
  EXPECT_NEAR(rig.rightInLeft().translation().x(), 0.12, 1e-12);
  // Not a perfectly rectified pair: the right camera is rotated.
  EXPECT_GT(Eigen::AngleAxisd(rig.rightInLeft().linear()).angle(), 1e-3);
}

TEST(StereoRig, RectificationAlignsTheCameras) {
  const StereoRig rig{RigConfig{}};
  const auto& c = rig.calibration();
  // A point in the left raw frame lands on the same rectified row in both cameras.
  const Eigen::Vector3d p_left(0.3, -0.2, 2.5);
  const Eigen::Vector3d p_right = rig.rightInLeft().inverse() * p_left;
  // Both P project points given in the left rectified frame (the right P holds -fx * baseline).
  const cv::Vec3d in_rect_left = c.left.R * cv::Vec3d(p_left.x(), p_left.y(), p_left.z());
  const cv::Vec3d hl = c.left.P * cv::Vec4d(in_rect_left[0], in_rect_left[1], in_rect_left[2], 1.0);
  const cv::Point2d l(hl[0] / hl[2], hl[1] / hl[2]);
  const cv::Vec3d hr = c.right.P * cv::Vec4d(in_rect_left[0], in_rect_left[1], in_rect_left[2], 1.0);
  const cv::Point2d r(hr[0] / hr[2], hr[1] / hr[2]);
  EXPECT_NEAR(l.y, r.y, 1e-6);
  EXPECT_NEAR(l.x - r.x, c.disparityAtDepth(in_rect_left[2]), 1e-6);
  // ...and the right camera's own rectification (R2, then the rectified intrinsics) sees it there too.
  const cv::Vec3d own = c.right.R * cv::Vec3d(p_right.x(), p_right.y(), p_right.z());
  const cv::Matx33d k_rect(c.right.P(0, 0), 0, c.right.P(0, 2), 0, c.right.P(1, 1), c.right.P(1, 2), 0, 0, 1);
  const cv::Vec3d ho = k_rect * own;
  EXPECT_NEAR(ho[0] / ho[2], r.x, 1e-6);
  EXPECT_NEAR(ho[1] / ho[2], r.y, 1e-6);
}

TEST(StereoRig, RpyRotationOrderIsZyx) {
  const Eigen::Matrix3d r = rotationFromRpyDeg({0, 90, 0});
  EXPECT_LT((r * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitX()).norm(), 1e-12);
  const Eigen::Matrix3d q = rotationFromRpyDeg({90, 0, 90});
  // x first (y -> z), then z (x -> y): z stays z under the z rotation.
  EXPECT_LT((q * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
}
