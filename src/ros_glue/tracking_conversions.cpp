// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/tracking_conversions.h"

#include <Eigen/Eigenvalues>

#include <algorithm>

#include "underwater_stereo/ros_glue/detection_conversions.h"

namespace underwater_stereo {
namespace ros_glue {

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).normalized().toRotationMatrix();
  out.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  return out;
}

void fillTrackFields(const Track& track, const Eigen::Matrix3d& rotation, DetectedObject& o) {
  o.track_id = track.id;
  o.label = track.label;
  const Eigen::Vector3d v = rotation * track.filter.velocity();
  o.velocity.x = v.x();
  o.velocity.y = v.y();
  o.velocity.z = v.z();
  const Eigen::Matrix3d c = rotation * track.filter.positionCovariance() * rotation.transpose();
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) o.position_covariance[static_cast<std::size_t>(3 * r + k)] = c(r, k);
  }
  o.observations = track.observations;
  o.last_seen.fromSec(track.last_seen_s);
}

DetectedObjectArray toLandmarksMsg(const std::vector<Track>& tracks, const std_msgs::Header& header,
                                   const Eigen::Isometry3d& camera_pose) {
  DetectedObjectArray msg;
  msg.header = header;
  for (const Track& t : tracks) {
    if (t.status != TrackStatus::kConfirmed) continue;
    DetectedObject o;
    o.id = static_cast<std::uint32_t>(msg.objects.size());
    o.colour = t.colour;
    o.shape = shapeName(t.shape);
    o.size.x = t.size_m.x();
    o.size.y = t.size_m.y();
    o.size.z = t.size_m.z();
    const Eigen::Vector3d p = t.filter.position();
    o.position.x = p.x();
    o.position.y = p.y();
    o.position.z = p.z();
    o.range = static_cast<float>((p - camera_pose.translation()).norm());
    o.orientation.w = 1.0;
    fillTrackFields(t, Eigen::Matrix3d::Identity(), o);
    msg.objects.push_back(o);
  }
  return msg;
}

std::string trackFrameName(const std::string& prefix, const DetectedObject& landmark) {
  return prefix + (landmark.label.empty() ? landmark.colour : landmark.label) + "_" + std::to_string(landmark.track_id);
}

std::vector<geometry_msgs::TransformStamped> toTrackTransforms(const DetectedObjectArray& landmarks,
                                                               const std::string& prefix) {
  std::vector<geometry_msgs::TransformStamped> out;
  for (const DetectedObject& o : landmarks.objects) {
    geometry_msgs::TransformStamped t;
    t.header = landmarks.header;
    t.child_frame_id = trackFrameName(prefix, o);
    t.transform.translation.x = o.position.x;
    t.transform.translation.y = o.position.y;
    t.transform.translation.z = o.position.z;
    t.transform.rotation = o.orientation;
    out.push_back(t);
  }
  return out;
}

visualization_msgs::MarkerArray toLandmarkMarkers(const DetectedObjectArray& landmarks) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker clear;
  clear.header = landmarks.header;
  clear.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(clear);
  for (const DetectedObject& o : landmarks.objects) {
    Eigen::Matrix3d c;
    for (int r = 0; r < 3; ++r) {
      for (int k = 0; k < 3; ++k) c(r, k) = o.position_covariance[static_cast<std::size_t>(3 * r + k)];
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(c);
    Eigen::Matrix3d axes = eigen.eigenvectors();
    if (axes.determinant() < 0) axes.col(2) *= -1.0;  // a rotation, not a reflection
    const Eigen::Quaterniond q(axes);
    visualization_msgs::Marker ellipsoid;
    ellipsoid.header = landmarks.header;
    ellipsoid.ns = "covariance";
    ellipsoid.id = static_cast<int>(o.track_id);
    ellipsoid.type = visualization_msgs::Marker::SPHERE;
    ellipsoid.action = visualization_msgs::Marker::ADD;
    ellipsoid.pose.position = o.position;
    ellipsoid.pose.orientation.x = q.x();
    ellipsoid.pose.orientation.y = q.y();
    ellipsoid.pose.orientation.z = q.z();
    ellipsoid.pose.orientation.w = q.w();
    const Eigen::Vector3d sigma = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    ellipsoid.scale.x = std::max(0.005, 4.0 * sigma.x());  // 2 sigma each way
    ellipsoid.scale.y = std::max(0.005, 4.0 * sigma.y());
    ellipsoid.scale.z = std::max(0.005, 4.0 * sigma.z());
    ellipsoid.color = displayColour(o.colour, cv::Scalar(255, 255, 255));
    ellipsoid.color.a = 0.5F;
    out.markers.push_back(ellipsoid);
    visualization_msgs::Marker text = ellipsoid;
    text.ns = "landmark";
    text.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    text.pose.orientation = geometry_msgs::Quaternion();
    text.pose.orientation.w = 1.0;
    text.pose.position.z += std::max(o.size.x, std::max(o.size.y, o.size.z)) / 2 + 0.1;  // above it (z up in a fixed frame)
    text.scale.x = text.scale.y = 0.0;
    text.scale.z = 0.1;
    text.color.r = text.color.g = text.color.b = text.color.a = 1.0F;
    text.text = (o.label.empty() ? o.colour : o.label) + " #" + std::to_string(o.track_id);
    out.markers.push_back(text);
  }
  return out;
}

}  // namespace ros_glue
}  // namespace underwater_stereo
