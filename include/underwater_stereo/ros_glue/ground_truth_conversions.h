// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Simulator ground truth -> underwater_stereo/GroundTruth.

#include <geometry_msgs/TransformStamped.h>
#include <std_msgs/Header.h>
#include <underwater_stereo/GroundTruth.h>

#include <vector>

#include "underwater_stereo/common/ground_truth.h"

namespace underwater_stereo {
namespace ros_glue {

/// `camera_pose_world`: the left optical frame in the scene's world frame (RenderedPair::camera_pose);
/// `fixed_frame`: the name under which the world frame is published (sim::fixedFromWorld()), e.g. "odom".
GroundTruth toGroundTruthMsg(const std::vector<sim::GroundTruthObject>& objects, const std_msgs::Header& header,
                             const Eigen::Isometry3d& camera_pose_world, const std::string& fixed_frame);

/// The left optical frame's pose as TF `fixed_frame` -> header.frame_id at header.stamp.
geometry_msgs::TransformStamped toCameraTransform(const Eigen::Isometry3d& camera_pose_world,
                                                 const std_msgs::Header& header, const std::string& fixed_frame);

}  // namespace ros_glue
}  // namespace underwater_stereo
