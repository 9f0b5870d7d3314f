// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <limits>

#include "sim_test_helpers.h"
#include "underwater_stereo/detection/roi_stereo_matcher.h"
#include "underwater_stereo/sim/renderer.h"

using namespace underwater_stereo;

namespace {

struct GreyPair {
  cv::Mat left, right;
  StereoCalibration calibration;
};

GreyPair texturedPanelAt(double depth) {
  sim::SceneObject panel;
  panel.name = "panel";
  panel.shape = sim::ShapeType::kPanel;
  panel.colour = "white";
  panel.position_m = {0, 0, depth};
  panel.size_m = {8, 6, 0};
  panel.texture = 0.8;
  const sim::Renderer renderer(sim::test::smallScene(panel));
  const sim::RenderedPair pair = renderer.render(0, 0);
  GreyPair out;
  cv::cvtColor(pair.left, out.left, cv::COLOR_BGR2GRAY);
  cv::cvtColor(pair.right, out.right, cv::COLOR_BGR2GRAY);
  out.calibration = renderer.calibration();
  return out;
}

}  // namespace

TEST(RoiStereoMatcher, PointsOfAPanelLieAtItsDepth) {
  const GreyPair pair = texturedPanelAt(2.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  const cv::Rect roi(300, 180, 60, 50);
  const RoiPoints pts = matcher.match(pair.left, pair.right, roi, cv::Mat(roi.size(), CV_8UC1, cv::Scalar(255)));
  ASSERT_GT(pts.points.size(), 500U);
  EXPECT_GT(pts.matched_pixels, 0.9 * pts.mask_pixels);
  std::vector<float> z;
  for (const auto& p : pts.points) z.push_back(p.z());
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  EXPECT_NEAR(z[z.size() / 2], 2.0, 0.02);
}

TEST(RoiStereoMatcher, RoiAtTheLeftEdgeNeitherThrowsNorCrashes) {
  const GreyPair pair = texturedPanelAt(2.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  for (const cv::Rect roi : {cv::Rect(0, 100, 20, 30), cv::Rect(0, 370, 30, 30), cv::Rect(610, 0, 30, 20)}) {
    EXPECT_NO_THROW(matcher.match(pair.left, pair.right, roi, cv::Mat(roi.size(), CV_8UC1, cv::Scalar(255)))) << roi;
  }
}

TEST(RoiStereoMatcher, BadInputThrows) {
  const GreyPair pair = texturedPanelAt(2.0);
  const RoiStereoMatcher matcher(pair.calibration, StereoMatchConfig{});
  const cv::Rect roi(300, 180, 60, 50);
  const cv::Mat mask(roi.size(), CV_8UC1, cv::Scalar(255));
  EXPECT_THROW(matcher.match(pair.left, pair.right(cv::Rect(0, 0, 320, 200)), roi, mask), std::invalid_argument);
  EXPECT_THROW(matcher.match(pair.left, pair.right, cv::Rect(600, 380, 60, 50), mask), std::invalid_argument);
  EXPECT_THROW(matcher.match(pair.left, pair.right, roi, cv::Mat(10, 10, CV_8UC1)), std::invalid_argument);
  cv::Mat colour;
  cv::cvtColor(pair.left, colour, cv::COLOR_GRAY2BGR);
  EXPECT_THROW(matcher.match(colour, pair.right, roi, mask), std::invalid_argument);
}

TEST(RoiStereoMatcher, InvalidCalibrationOrConfigIsRefused) {
  StereoCalibration c = texturedPanelAt(2.0).calibration;
  StereoMatchConfig bad;
  bad.min_depth_m = 6.0;
  bad.block_size = 4;
  EXPECT_EQ(bad.validate().size(), 2U);
  EXPECT_THROW(RoiStereoMatcher(c, bad), std::invalid_argument);
  c.right.P(0, 3) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(RoiStereoMatcher(c, StereoMatchConfig{}), std::invalid_argument);
}
