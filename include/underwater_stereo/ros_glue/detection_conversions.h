// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file DetectionResult -> ROS messages: objects, markers and the objects' point cloud.

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

/// The colour to draw an object of designated colour `colour` in: the colour's common name (red, orange,
/// yellow, green, blue, purple, white, black; the measured colour carries the water's cast), else the measured
/// colour (B, G, R 0-255) brightened.
std_msgs::ColorRGBA displayColour(const std::string& colour, const cv::Scalar& measured_bgr);

}  // namespace ros_glue
}  // namespace underwater_stereo
