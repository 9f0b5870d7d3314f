// SPDX-License-Identifier: BSD-3-Clause
// Every message of the package survives serialisation unchanged.
#include <gtest/gtest.h>
#include <ros/serialization.h>
#include <underwater_stereo/DetectedObjectArray.h>
#include <underwater_stereo/GroundTruth.h>

namespace {

template <typename M>
M roundTrip(const M& in) {
  namespace ser = ros::serialization;
  const std::uint32_t size = ser::serializationLength(in);
  std::vector<std::uint8_t> buffer(size);
  ser::OStream out(buffer.data(), size);
  ser::serialize(out, in);
  M result;
  ser::IStream stream(buffer.data(), size);
  ser::deserialize(stream, result);
  return result;
}

}  // namespace

TEST(Messages, DetectedObjectArrayRoundTrips) {
  underwater_stereo::DetectedObjectArray in;
  in.header.stamp = ros::Time(1234, 5678);
  in.header.frame_id = "stereo_left_optical_frame";
  in.quality.status = underwater_stereo::ImageQuality::TOO_DARK;
  in.quality.mean_brightness = 17.5F;
  in.quality.dark_fraction = 0.8F;
  in.quality.bright_fraction = 0.01F;
  in.quality.enhanced = true;
  in.processing_time_ms = 12.25F;
  underwater_stereo::DetectedObject o;
  o.id = 3;
  o.colour = "red";
  o.measured_colour.r = 0.7F;
  o.shape = underwater_stereo::DetectedObject::SHAPE_CYLINDER;
  o.outline = underwater_stereo::DetectedObject::OUTLINE_RECTANGLE;
  o.size.x = 0.11;
  o.size.z = 0.9;
  o.range = 4.1F;
  o.position.x = 0.1;
  o.position.z = 4.0;
  o.orientation.w = 1.0;
  o.roi.x_offset = 10;
  o.roi.width = 200;
  o.confidence = 0.9F;
  o.num_points = 4242;
  o.fit_rmse = 0.004F;
  o.cut_by_border = true;
  in.objects.push_back(o);
  in.objects.push_back(o);
  const auto out = roundTrip(in);
  EXPECT_EQ(out, in);
  EXPECT_EQ(out.objects[1].shape, "cylinder");
  EXPECT_EQ(out.objects[1].outline, "rectangle");
  EXPECT_TRUE(out.objects[1].cut_by_border);
}

TEST(Messages, GroundTruthRoundTrips) {
  underwater_stereo::GroundTruth in;
  in.header.frame_id = "stereo_left_optical_frame";
  underwater_stereo::GroundTruthObject o;
  o.name = "red_buoy";
  o.shape = "sphere";
  o.colour = "red";
  o.range = 2.5F;
  o.visible_pixels = 1500;
  o.roi.height = 40;
  in.objects.push_back(o);
  EXPECT_EQ(roundTrip(in), in);
}
