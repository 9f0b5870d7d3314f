// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>
#include <image_geometry/stereo_camera_model.h>

#include "underwater_stereo/ros_glue/calibration_conversions.h"
#include "underwater_stereo/sim/stereo_rig.h"

using namespace underwater_stereo;

TEST(CalibrationConversions, RoundTripsThroughCameraInfo) {
  const StereoCalibration calib = sim::StereoRig(sim::RigConfig{}).calibration();
  const sensor_msgs::CameraInfo info = ros_glue::toCameraInfo(calib.right);
  EXPECT_EQ(info.distortion_model, "plumb_bob");
  const CameraCalibration back = ros_glue::fromCameraInfo(info);
  EXPECT_EQ(back.width, calib.right.width);
  EXPECT_EQ(back.height, calib.right.height);
  EXPECT_EQ(cv::norm(back.K, calib.right.K, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(back.R, calib.right.R, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(back.P, calib.right.P, cv::NORM_INF), 0.0);
  EXPECT_EQ(back.D, calib.right.D);
}

TEST(CalibrationConversions, StereoCameraModelAgreesWithTheRig) {
  const StereoCalibration calib = sim::StereoRig(sim::RigConfig{}).calibration();
  sensor_msgs::CameraInfo left = ros_glue::toCameraInfo(calib.left), right = ros_glue::toCameraInfo(calib.right);
  left.header.frame_id = "stereo_left_optical_frame";
  right.header.frame_id = "stereo_left_optical_frame";  // StereoCameraModel requires one frame for both
  image_geometry::StereoCameraModel model;
  ASSERT_TRUE(model.fromCameraInfo(left, right));
  EXPECT_NEAR(model.baseline(), calib.baselineM(), 1e-9);
  EXPECT_NEAR(model.baseline(), 0.12, 0.003);
  for (const double z : {0.5, 1.0, 2.5, 5.0}) {
    EXPECT_NEAR(model.getDisparity(z), calib.disparityAtDepth(z), 1e-9);
    cv::Point3d xyz;
    model.projectDisparityTo3d(cv::Point2d(700, 500), model.getDisparity(z), xyz);
    EXPECT_NEAR(xyz.z, z, 1e-6 * z);  // image_geometry computes in float
  }
  // A point projects into both rectified images on the same row, disparity f*B/Z apart.
  const cv::Point3d p(0.3, -0.2, 2.0);
  const cv::Point2d l = model.left().project3dToPixel(p);
  const cv::Point2d r = model.right().project3dToPixel(p);
  EXPECT_NEAR(l.y, r.y, 1e-9);
  EXPECT_NEAR(l.x - r.x, calib.disparityAtDepth(2.0), 1e-9);
}
