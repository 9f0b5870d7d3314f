// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/ground_truth_conversions.h"

namespace underwater_stereo {
namespace ros_glue {

GroundTruth toGroundTruthMsg(const std::vector<sim::GroundTruthObject>& objects, const std_msgs::Header& header) {
  GroundTruth msg;
  msg.header = header;
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
