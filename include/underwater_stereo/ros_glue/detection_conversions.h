// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file DetectionResult -> ROS messages: objects, markers, the objects' point cloud and their TF frames.

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>
#include <visualization_msgs/MarkerArray.h>

#include <string>
#include <vector>

#include "underwater_stereo/DetectedObjectArray.h"
#include "underwater_stereo/detection/detector.h"

namespace underwater_stereo {
namespace ros_glue {

ImageQuality toQualityMsg(const QualityReport& quality);

/// `header`: the pair's stamp and the left optical frame.
DetectedObjectArray toObjectsMsg(const DetectionResult& result, const std_msgs::Header& header);

/// A DELETEALL marker, then per object its fitted shape (sphere, cylinder, cube; a thin cube for a plane)
/// in its measured size and orientation, drawn in its designated colour (red, orange, yellow, green, blue,
/// purple, white, black; other class names in the measured colour), and a text label above it (namespaces
/// "shape" and "label").
visualization_msgs::MarkerArray toMarkers(const DetectionResult& result, const std_msgs::Header& header);

/// The objects' 3D points: x, y, z (float32) and rgb (the object's display colour, packed as rviz reads it).
sensor_msgs::PointCloud2 toCloud(const DetectionResult& result, const std_msgs::Header& header);

/// One transform per object, `<prefix>object_<id>`, child of header.frame_id.
std::vector<geometry_msgs::TransformStamped> toTransforms(const DetectionResult& result, const std_msgs::Header& header,
                                                          const std::string& prefix);

}  // namespace ros_glue
}  // namespace underwater_stereo
