// SPDX-License-Identifier: BSD-3-Clause
// The simulator's geometry judged by OpenCV alone: where cv::projectPoints puts known 3D points in both raw
// cameras, and where cv::stereoRectify's rectification puts them, must be where the renderer draws them.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "sim_test_helpers.h"
#include "underwater_stereo/sim/renderer.h"

using namespace underwater_stereo;
using namespace underwater_stereo::sim;

namespace {

/// Small white balls on black: no water, no seabed, even light, so every ball is a sharp disc.
Scene ballsScene(const std::vector<Eigen::Vector3d>& centres) {
  Scene s = test::smallScene(test::sphere("ball_0", centres[0], 0.1));
  s.objects.clear();
  for (std::size_t i = 0; i < centres.size(); ++i) {
    SceneObject o = test::sphere("ball_" + std::to_string(i), centres[i], 0.1);
    o.albedo = {0.9, 0.9, 0.9};
    o.texture = 0.0;
    s.objects.push_back(o);
  }
  s.seabed.enabled = false;
  s.water.attenuation_per_m = Eigen::Vector3d::Zero();
  s.water.veiling_light = Eigen::Vector3d::Zero();
  s.light.ambient = 1.0;
  s.light.lamp_intensity = 0.0;
  return s;
}

/// Centroids of the bright blobs of a BGR image, nearest first to each of `near` (the expected positions).
std::vector<cv::Point2d> blobCentroids(const cv::Mat& bgr, const std::vector<cv::Point2d>& near) {
  cv::Mat grey, mask, labels, stats, centroids;
  cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
  cv::threshold(grey, mask, 60, 255, cv::THRESH_BINARY);
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids);
  std::vector<cv::Point2d> out;
  for (const cv::Point2d& p : near) {
    cv::Point2d best(-1e9, -1e9);
    for (int k = 1; k < n; ++k) {
      const cv::Point2d c(centroids.at<double>(k, 0), centroids.at<double>(k, 1));
      if (cv::norm(c - p) < cv::norm(best - p)) best = c;
    }
    out.push_back(best);
  }
  return out;
}

}  // namespace

TEST(SimGeometryOpenCv, RenderedBallsSitWhereOpenCvProjectsAndRectifiesThem) {
  const std::vector<Eigen::Vector3d> centres{{0.0, 0.0, 1.5}, {0.5, -0.3, 2.0}, {-0.7, 0.35, 2.5}, {0.9, 0.4, 3.5},
                                             {-1.1, -0.5, 4.0}};
  const Renderer renderer(ballsScene(centres));
  const StereoRig& rig = renderer.rig();
  const RenderedPair pair = renderer.render(0.0, 0);
  std::vector<cv::Point3d> points;
  for (const auto& c : centres) points.emplace_back(c.x(), c.y(), c.z());

  // Left raw camera: the centroid of each ball's pixels (exact truth labels) against cv::projectPoints.
  std::vector<cv::Point2d> left_expected;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Mat(rig.left().K), cv::Mat(rig.left().D),
                    left_expected);
  std::vector<cv::Point2d> left_seen;
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const cv::Moments m = cv::moments(pair.left_labels == static_cast<int>(i + 1), true);
    ASSERT_GT(m.m00, 100) << "ball " << i;
    left_seen.emplace_back(m.m10 / m.m00, m.m01 / m.m00);
    EXPECT_NEAR(left_seen[i].x, left_expected[i].x, 0.3) << "ball " << i;
    EXPECT_NEAR(left_seen[i].y, left_expected[i].y, 0.3) << "ball " << i;
  }

  // Right raw camera: OpenCV's pose convention (x_right = R x_left + T) from the rig's right-in-left pose.
  const Eigen::Isometry3d left_to_right = rig.rightInLeft().inverse();
  cv::Matx33d R;
  cv::Vec3d T;
  for (int r = 0; r < 3; ++r) {
    T[r] = left_to_right.translation()[r];
    for (int c = 0; c < 3; ++c) R(r, c) = left_to_right.linear()(r, c);
  }
  cv::Vec3d rvec;
  cv::Rodrigues(R, rvec);
  std::vector<cv::Point2d> right_expected;
  cv::projectPoints(points, rvec, T, cv::Mat(rig.right().K), cv::Mat(rig.right().D), right_expected);
  const std::vector<cv::Point2d> right_seen = blobCentroids(pair.right, right_expected);
  for (std::size_t i = 0; i < centres.size(); ++i) {
    EXPECT_NEAR(right_seen[i].x, right_expected[i].x, 0.3) << "ball " << i;
    EXPECT_NEAR(right_seen[i].y, right_expected[i].y, 0.3) << "ball " << i;
  }

  // Rectification computed here by cv::stereoRectify must be the calibration the simulator hands out...
  cv::Mat R1, R2, P1, P2, Q;
  const cv::Size size(rig.left().width, rig.left().height);
  cv::stereoRectify(cv::Mat(rig.left().K), cv::Mat(rig.left().D), cv::Mat(rig.right().K), cv::Mat(rig.right().D), size,
                    cv::Mat(R), cv::Mat(T), R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 0.0, size);
  const StereoCalibration& calib = renderer.calibration();
  EXPECT_LT(cv::norm(cv::Matx33d(R1) - calib.left.R), 1e-9);
  EXPECT_LT(cv::norm(cv::Matx33d(R2) - calib.right.R), 1e-9);
  EXPECT_LT(cv::norm(cv::Matx34d(P1) - calib.left.P), 1e-6);
  EXPECT_LT(cv::norm(cv::Matx34d(P2) - calib.right.P), 1e-6);
  EXPECT_NEAR(calib.baselineM(), cv::norm(T), 1e-9);

  // ...and the rendered balls, rectified with it, lie on one row with disparity f * B / z (z in the rectified frame).
  std::vector<cv::Point2d> left_rect, right_rect;
  cv::undistortPoints(left_seen, left_rect, cv::Mat(rig.left().K), cv::Mat(rig.left().D), R1, P1);
  cv::undistortPoints(right_seen, right_rect, cv::Mat(rig.right().K), cv::Mat(rig.right().D), R2, P2);
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const cv::Vec3d in_rect = cv::Matx33d(R1) * cv::Vec3d(points[i].x, points[i].y, points[i].z);
    EXPECT_NEAR(left_rect[i].y, right_rect[i].y, 0.3) << "ball " << i;
    EXPECT_NEAR(left_rect[i].x - right_rect[i].x, calib.disparityAtDepth(in_rect[2]), 0.3) << "ball " << i;
  }
}
