// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/detection_conversions.h"

#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <array>
#include <map>
#include <cstdio>
#include <cstring>

namespace underwater_stereo {
namespace ros_glue {
namespace {

geometry_msgs::Quaternion toMsg(const Eigen::Quaterniond& q) {
  geometry_msgs::Quaternion m;
  m.x = q.x();
  m.y = q.y();
  m.z = q.z();
  m.w = q.w();
  return m;
}

}  // namespace

std_msgs::ColorRGBA displayColour(const std::string& colour, const cv::Scalar& measured_bgr) {
  static const std::map<std::string, std::array<float, 3>> kNamed{
      {"red", {1.0F, 0.1F, 0.1F}},    {"orange", {1.0F, 0.55F, 0.0F}}, {"yellow", {1.0F, 0.9F, 0.1F}},
      {"green", {0.1F, 0.85F, 0.2F}}, {"blue", {0.1F, 0.3F, 1.0F}},    {"purple", {0.6F, 0.2F, 0.8F}},
      {"white", {1.0F, 1.0F, 1.0F}},  {"black", {0.2F, 0.2F, 0.2F}}};
  std_msgs::ColorRGBA c;
  c.a = 0.8F;
  const auto named = kNamed.find(colour);
  if (named != kNamed.end()) {
    c.r = named->second[0];
    c.g = named->second[1];
    c.b = named->second[2];
    return c;
  }
  const double peak = std::max({measured_bgr[0], measured_bgr[1], measured_bgr[2], 1.0});
  c.r = static_cast<float>(measured_bgr[2] / peak);
  c.g = static_cast<float>(measured_bgr[1] / peak);
  c.b = static_cast<float>(measured_bgr[0] / peak);
  return c;
}

ImageQuality toQualityMsg(const QualityReport& q) {
  ImageQuality m;
  m.status = static_cast<std::uint8_t>(q.status);
  m.mean_brightness = static_cast<float>(q.mean_brightness);
  m.dark_fraction = static_cast<float>(q.dark_fraction);
  m.bright_fraction = static_cast<float>(q.bright_fraction);
  m.enhanced = q.enhanced;
  return m;
}

DetectedObjectArray toObjectsMsg(const DetectionResult& result, const std_msgs::Header& header) {
  DetectedObjectArray msg;
  msg.header = header;
  msg.quality = toQualityMsg(result.quality);
  msg.processing_time_ms = static_cast<float>(result.timings.total_ms);
  for (std::size_t i = 0; i < result.objects.size(); ++i) {
    const Detection& d = result.objects[i];
    DetectedObject o;
    o.id = static_cast<std::uint32_t>(i);
    o.colour = d.colour;
    o.measured_colour.r = static_cast<float>(d.measured_bgr[2] / 255.0);
    o.measured_colour.g = static_cast<float>(d.measured_bgr[1] / 255.0);
    o.measured_colour.b = static_cast<float>(d.measured_bgr[0] / 255.0);
    o.measured_colour.a = 1.0F;
    o.shape = shapeName(d.shape);
    o.outline = outlineName(d.outline);
    o.size.x = d.size_m.x();
    o.size.y = d.size_m.y();
    o.size.z = d.size_m.z();
    o.range = static_cast<float>(d.range_m);
    o.position.x = d.position_m.x();
    o.position.y = d.position_m.y();
    o.position.z = d.position_m.z();
    o.orientation = toMsg(d.orientation);
    o.roi.x_offset = static_cast<std::uint32_t>(d.roi.x);
    o.roi.y_offset = static_cast<std::uint32_t>(d.roi.y);
    o.roi.width = static_cast<std::uint32_t>(d.roi.width);
    o.roi.height = static_cast<std::uint32_t>(d.roi.height);
    o.confidence = static_cast<float>(d.confidence);
    o.num_points = static_cast<std::uint32_t>(d.points.size());
    o.fit_rmse = static_cast<float>(d.fit_rmse_m);
    o.cut_by_border = d.cut_by_border;
    msg.objects.push_back(o);
  }
  return msg;
}

visualization_msgs::MarkerArray toMarkers(const DetectionResult& result, const std_msgs::Header& header) {
  visualization_msgs::MarkerArray out;
  visualization_msgs::Marker clear;
  clear.header = header;
  clear.action = visualization_msgs::Marker::DELETEALL;
  out.markers.push_back(clear);
  for (std::size_t i = 0; i < result.objects.size(); ++i) {
    const Detection& d = result.objects[i];
    visualization_msgs::Marker shape;
    shape.header = header;
    shape.ns = "shape";
    shape.id = static_cast<int>(i);
    shape.action = visualization_msgs::Marker::ADD;
    shape.pose.position.x = d.position_m.x();
    shape.pose.position.y = d.position_m.y();
    shape.pose.position.z = d.position_m.z();
    shape.pose.orientation = toMsg(d.orientation);
    shape.scale.x = std::max(0.01, d.size_m.x());
    shape.scale.y = std::max(0.01, d.size_m.y());
    shape.scale.z = std::max(0.01, d.size_m.z());
    shape.color = displayColour(d.colour, d.measured_bgr);
    switch (d.shape) {
      case ShapeKind::kSphere:
        shape.type = visualization_msgs::Marker::SPHERE;
        break;
      case ShapeKind::kCylinder:
        shape.type = visualization_msgs::Marker::CYLINDER;
        break;
      case ShapeKind::kBox:
      case ShapeKind::kPlane:    // thin
      case ShapeKind::kUnknown:  // the points' extents
        shape.type = visualization_msgs::Marker::CUBE;
        break;
    }
    out.markers.push_back(shape);
    visualization_msgs::Marker text = shape;
    text.ns = "label";
    text.type = visualization_msgs::Marker::TEXT_VIEW_FACING;
    text.pose.orientation = toMsg(Eigen::Quaterniond::Identity());
    text.pose.position.y -= d.size_m.maxCoeff() / 2 + 0.08;  // above it (optical frame: y down)
    text.scale.x = text.scale.y = 0.0;
    text.scale.z = 0.08;
    text.color.r = text.color.g = text.color.b = text.color.a = 1.0F;
    char buf[96];
    std::snprintf(buf, sizeof buf, "%s %s %.2f m @ %.2f m", d.colour.c_str(), shapeName(d.shape), d.size_m.maxCoeff(),
                  d.range_m);
    text.text = buf;
    out.markers.push_back(text);
  }
  return out;
}

sensor_msgs::PointCloud2 toCloud(const DetectionResult& result, const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header;
  std::size_t n = 0;
  for (const Detection& d : result.objects) n += d.points.size();
  sensor_msgs::PointCloud2Modifier modifier(cloud);
  modifier.setPointCloud2FieldsByString(2, "xyz", "rgb");
  modifier.resize(n);
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(n);
  sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
  sensor_msgs::PointCloud2Iterator<std::uint8_t> rgb(cloud, "rgb");
  for (const Detection& d : result.objects) {
    const std_msgs::ColorRGBA c = displayColour(d.colour, d.measured_bgr);
    for (const Eigen::Vector3f& p : d.points) {
      *x = p.x();
      *y = p.y();
      *z = p.z();
      rgb[0] = static_cast<std::uint8_t>(c.b * 255);
      rgb[1] = static_cast<std::uint8_t>(c.g * 255);
      rgb[2] = static_cast<std::uint8_t>(c.r * 255);
      ++x;
      ++y;
      ++z;
      ++rgb;
    }
  }
  return cloud;
}

}  // namespace ros_glue
}  // namespace underwater_stereo
