// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include "underwater_stereo/ros_glue/tracking_conversions.h"

using namespace underwater_stereo;

namespace {

Tracker trackerWithOneLandmark() {
  TrackingConfig config;
  config.targets = {{"red_buoy", "red", ShapeKind::kSphere, 0.25, 0.3}};
  config.confirm_hits = 2;
  Tracker tracker(config);
  TrackingFrame f;
  Observation o;
  o.colour = "red";
  o.shape = ShapeKind::kSphere;
  o.size_m = Eigen::Vector3d::Constant(0.25);
  o.target = 0;
  o.position_m = {0.5, 0.0, 2.0};
  Observation other = o;
  other.colour = "green";
  other.target = -1;
  other.position_m = {-0.5, 0, 3};
  f.observations = {o, other};
  f.camera_pose.translation() = Eigen::Vector3d(1, 0, 0);
  tracker.update(f);
  f.stamp_s = 0.5;
  f.observations = {o};
  tracker.update(f);
  return tracker;
}

}  // namespace

TEST(TrackingConversions, LandmarksHoldConfirmedTracksWithTheirFields) {
  const Tracker tracker = trackerWithOneLandmark();
  std_msgs::Header h;
  h.frame_id = "odom";
  h.stamp = ros::Time(0.5);
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
  camera.translation() = Eigen::Vector3d(1, 0, 0);
  const DetectedObjectArray landmarks = ros_glue::toLandmarksMsg(tracker.tracks(), h, camera);
  ASSERT_EQ(landmarks.objects.size(), 1U) << "the green track is tentative";
  const DetectedObject& o = landmarks.objects[0];
  EXPECT_EQ(o.track_id, 1U);
  EXPECT_EQ(o.label, "red_buoy");
  EXPECT_EQ(o.observations, 2U);
  EXPECT_NEAR(o.position.x, 1.5, 1e-6);
  EXPECT_NEAR(o.range, std::hypot(0.5, 2.0), 1e-4);
  EXPECT_DOUBLE_EQ(o.last_seen.toSec(), 0.5);
  EXPECT_GT(o.position_covariance[0], 0.0);
  EXPECT_DOUBLE_EQ(o.position_covariance[1], o.position_covariance[3]);
  const auto tfs = ros_glue::toTrackTransforms(landmarks, "uws/");
  ASSERT_EQ(tfs.size(), 1U);
  EXPECT_EQ(tfs[0].child_frame_id, "uws/red_buoy_1");
  EXPECT_EQ(tfs[0].header.frame_id, "odom");
  DetectedObject unlabelled = o;
  unlabelled.label.clear();
  EXPECT_EQ(ros_glue::trackFrameName("", unlabelled), "red_1");
  const auto markers = ros_glue::toLandmarkMarkers(landmarks);
  ASSERT_EQ(markers.markers.size(), 3U);
  EXPECT_EQ(markers.markers[0].action, visualization_msgs::Marker::DELETEALL);
  EXPECT_EQ(markers.markers[1].ns, "covariance");
  EXPECT_NEAR(markers.markers[1].scale.x * markers.markers[1].scale.y * markers.markers[1].scale.z,
              64.0 * std::sqrt(Eigen::Map<const Eigen::Matrix3d>(o.position_covariance.data()).determinant()), 1e-9);
  EXPECT_EQ(markers.markers[2].text, "red_buoy #1");
}

TEST(TrackingConversions, TrackFieldsRotateIntoTheMessageFrame) {
  const Tracker tracker = trackerWithOneLandmark();
  const Track& t = tracker.tracks()[0];
  DetectedObject o;
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  ros_glue::fillTrackFields(t, rotation, o);
  const Eigen::Matrix3d c = rotation * t.filter.positionCovariance() * rotation.transpose();
  EXPECT_NEAR(o.position_covariance[8], c(2, 2), 1e-12);
  EXPECT_NEAR(o.velocity.z, (rotation * t.filter.velocity()).z(), 1e-12);
  geometry_msgs::Transform tf;
  tf.translation.x = 1;
  tf.rotation.y = std::sin(M_PI / 4);
  tf.rotation.w = std::cos(M_PI / 4);
  const Eigen::Isometry3d iso = ros_glue::toIsometry(tf);
  EXPECT_TRUE(iso.linear().isApprox(rotation, 1e-12));
  EXPECT_DOUBLE_EQ(iso.translation().x(), 1.0);
}
