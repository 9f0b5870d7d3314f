// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The detector's tracking in ROS: targets, tracks in the fixed frame (tf2), landmarks, their markers
/// and TF frames, the ~reset_tracks and ~get_landmark services and a diagnostic.

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/node_handle.h>
#include <ros/service_server.h>
#include <std_msgs/Header.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "underwater_stereo/DetectedObjectArray.h"
#include "underwater_stereo/GetLandmark.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/tracking/camera_view.h"
#include "underwater_stereo/tracking/target_matcher.h"
#include "underwater_stereo/tracking/tracker.h"

namespace underwater_stereo {
namespace ros_glue {

/// Private parameters (of the detector): tracking_config_file (default: the package's config/tracking.yaml),
/// fixed_frame ("" = track in the stereo frame), tf_timeout_s (0.05), publish_tf (true), object_frame_prefix ("").
class ObjectTracking {
 public:
  /// Reads the parameters and the tracking configuration; every problem is appended to `problems` (the
  /// object must not be used then).
  ObjectTracking(const ros::NodeHandle& pnh, std::vector<std::string>& problems);

  /// Advertises ~landmarks, ~landmark_markers and the services ~reset_tracks, ~get_landmark.
  void start(ros::NodeHandle& pnh);

  /// One processed pair (`header`: its stamp and the left optical frame; `calibration`: the head's; `workspace`: the
  /// depths of the detector that processed it, for what the camera can see):
  /// labels the objects with targets, removes those the configuration rejects, tracks the rest. Returns the
  /// ~objects message (stereo frame) with the track fields; publishes the landmarks, their markers and TF.
  /// Called for one pair at a time, in stamp order. Never throws for bad input (reported in diagnose()).
  DetectedObjectArray track(DetectionResult& result, const std_msgs::Header& header, const StereoCalibration& calibration,
                            const StereoMatchConfig& workspace);

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat);

 private:
  /// The stereo frame's pose in the tracking frame at `header.stamp`, or nothing (tf2 could not say).
  std::optional<Eigen::Isometry3d> cameraPose(const std_msgs::Header& header);
  bool resetTracks(std_srvs::Trigger::Request& req, std_srvs::Trigger::Response& res);
  bool getLandmark(GetLandmark::Request& req, GetLandmark::Response& res);

  TrackingConfig config_;
  std::string config_file_, fixed_frame_, frame_prefix_;
  double tf_timeout_s_ = 0.05;
  bool publish_tf_ = true;
  std::unique_ptr<TargetMatcher> matcher_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  tf2_ros::TransformBroadcaster broadcaster_;
  ros::Publisher landmarks_pub_, markers_pub_;
  ros::ServiceServer reset_service_, landmark_service_;

  std::mutex mutex_;  ///< guards everything below (pairs arrive from workers, service calls from the callback queue)
  std::unique_ptr<Tracker> tracker_;
  std::optional<CameraView> view_;
  StereoCalibration view_calibration_;  ///< and the depths [m] view_ was built for
  double view_near_m_ = 0, view_far_m_ = 0;
  std::string tracking_frame_;   ///< the frame tracks live in: fixed_frame_, or the stereo frame while it has no TF
  bool fixed_frame_seen_ = false;
  Eigen::Isometry3d camera_pose_ = Eigen::Isometry3d::Identity();
  long untracked_pairs_ = 0, resets_ = 0, rejected_ = 0;
  std::string last_problem_, last_tf_error_;
  double last_problem_stamp_s_ = 0;
};

}  // namespace ros_glue
}  // namespace underwater_stereo
