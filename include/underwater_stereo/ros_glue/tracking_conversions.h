// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Tracks <-> ROS messages: the track fields of DetectedObject, landmarks, their markers and TF frames.

#include <geometry_msgs/Transform.h>
#include <geometry_msgs/TransformStamped.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "underwater_stereo/DetectedObjectArray.h"
#include "underwater_stereo/tracking/tracker.h"

namespace underwater_stereo {
namespace ros_glue {

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t);

/// Fills `o`'s track fields (track_id, label, velocity, position_covariance, observations, last_seen) from
/// `track`; `rotation` takes vectors from the tracking frame into the message's frame.
void fillTrackFields(const Track& track, const Eigen::Matrix3d& rotation, DetectedObject& o);

/// Every confirmed track as a DetectedObject in the tracking frame (`header.frame_id`): position, size, shape,
/// colour and the track fields; range from the camera at `camera_pose` (the left optical frame in the tracking
/// frame); orientation identity; id counts 0..n-1.
DetectedObjectArray toLandmarksMsg(const std::vector<Track>& tracks, const std_msgs::Header& header,
                                   const Eigen::Isometry3d& camera_pose);

/// `<prefix><label, or colour when unlabelled>_<track_id>`, e.g. "red_buoy_7".
std::string trackFrameName(const std::string& prefix, const DetectedObject& landmark);

/// One transform per landmark, named by trackFrameName(), child of the landmarks' frame.
std::vector<geometry_msgs::TransformStamped> toTrackTransforms(const DetectedObjectArray& landmarks,
                                                               const std::string& prefix);

/// A DELETEALL marker, then per landmark its covariance ellipsoid (2 sigma, namespace "covariance") in its
/// colour and a text "<label or colour> #<track_id>" above it (namespace "landmark").
visualization_msgs::MarkerArray toLandmarkMarkers(const DetectedObjectArray& landmarks);

}  // namespace ros_glue
}  // namespace underwater_stereo
