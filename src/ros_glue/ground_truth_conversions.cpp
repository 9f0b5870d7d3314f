// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/ground_truth_conversions.h"

namespace underwater_stereo {
namespace ros_glue {

geometry_msgs::TransformStamped toCameraTransform(const Eigen::Isometry3d& camera_pose_world,
                                                 const std_msgs::Header& header, const std::string& fixed_frame) {
  const Eigen::Isometry3d pose = sim::fixedFromWorld() * camera_pose_world;
  const Eigen::Quaterniond q(pose.linear());
  geometry_msgs::TransformStamped t;
  t.header.stamp = header.stamp;
  t.header.frame_id = fixed_frame;
  t.child_frame_id = header.frame_id;
  t.transform.translation.x = pose.translation().x();
  t.transform.translation.y = pose.translation().y();
  t.transform.translation.z = pose.translation().z();
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  t.transform.rotation.w = q.w();
  return t;
}

GroundTruth toGroundTruthMsg(const std::vector<sim::GroundTruthObject>& objects, const std_msgs::Header& header,
                             const Eigen::Isometry3d& camera_pose_world, const std::string& fixed_frame) {
  GroundTruth msg;
  msg.header = header;
  msg.fixed_frame_id = fixed_frame;
  const geometry_msgs::TransformStamped camera = toCameraTransform(camera_pose_world, header, fixed_frame);
  msg.camera_pose.position.x = camera.transform.translation.x;
  msg.camera_pose.position.y = camera.transform.translation.y;
  msg.camera_pose.position.z = camera.transform.translation.z;
  msg.camera_pose.orientation = camera.transform.rotation;
  for (const auto& o : objects) {
    GroundTruthObject m;
    m.name = o.name;
    m.shape = o.shape;
    m.colour = o.colour;
    m.albedo.r = static_cast<float>(o.albedo.x());
    m.albedo.g = static_cast<float>(o.albedo.y());
    m.albedo.b = static_cast<float>(o.albedo.z());
    m.albedo.a = 1.0F;
    m.size.x = o.size_m.x();
    m.size.y = o.size_m.y();
    m.size.z = o.size_m.z();
    m.position.x = o.centre_left_m.x();
    m.position.y = o.centre_left_m.y();
    m.position.z = o.centre_left_m.z();
    m.orientation.x = o.orientation_left.x();
    m.orientation.y = o.orientation_left.y();
    m.orientation.z = o.orientation_left.z();
    m.orientation.w = o.orientation_left.w();
    const Eigen::Vector3d fixed = sim::fixedFromWorld() * o.centre_world_m;
    m.position_fixed.x = fixed.x();
    m.position_fixed.y = fixed.y();
    m.position_fixed.z = fixed.z();
    m.range = static_cast<float>(o.range_m);
    m.visible_pixels = static_cast<std::uint32_t>(o.visible_pixels);
    m.roi.x_offset = static_cast<std::uint32_t>(o.roi_left.x);
    m.roi.y_offset = static_cast<std::uint32_t>(o.roi_left.y);
    m.roi.width = static_cast<std::uint32_t>(o.roi_left.width);
    m.roi.height = static_cast<std::uint32_t>(o.roi_left.height);
    msg.objects.push_back(m);
  }
  return msg;
}

}  // namespace ros_glue
}  // namespace underwater_stereo
