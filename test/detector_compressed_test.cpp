// SPDX-License-Identifier: BSD-3-Clause
// The detector nodelet's image/compressed (ros_glue::CompressedImagePublisher) in a running graph: JPEG of the
// annotated left image at compressed_scale (default 0.5) with the pair's header.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CompressedImage.h>

#include <mutex>
#include <set>
#include <vector>

#include "ros_test_helpers.h"
#include "underwater_stereo/DetectedObjectArray.h"
#include "underwater_stereo/ros_glue/compressed_image_publisher.h"

using namespace underwater_stereo;
using underwater_stereo::test::waitFor;

TEST(DetectorCompressed, HalfSizeJpegOfTheAnnotatedImageWithThePairsHeader) {
  ros::NodeHandle nh;
  std::mutex mutex;
  std::vector<sensor_msgs::CompressedImageConstPtr> images;
  std::set<ros::Time> object_stamps;
  ros::Subscriber image_sub = nh.subscribe<sensor_msgs::CompressedImage>(
      "/stereo/detector/image/compressed", 10, [&](const sensor_msgs::CompressedImageConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        images.push_back(m);
      });
  ros::Subscriber objects_sub = nh.subscribe<DetectedObjectArray>(
      "/stereo/detector/objects", 50, [&](const DetectedObjectArrayConstPtr& m) {
        std::lock_guard<std::mutex> lock(mutex);
        object_stamps.insert(m->header.stamp);
      });
  ros::AsyncSpinner spinner(2);
  spinner.start();
  ASSERT_TRUE(waitFor([&] {
    std::lock_guard<std::mutex> lock(mutex);
    return images.size() >= 3;
  }, 60)) << "fewer than 3 image/compressed messages in 60 s";
  std::lock_guard<std::mutex> lock(mutex);
  for (const auto& m : images) {
    EXPECT_EQ(m->format, "jpeg");
    EXPECT_EQ(m->header.frame_id, "stereo_left_optical_frame");
    EXPECT_EQ(object_stamps.count(m->header.stamp), 1U) << "no objects message with the image's stamp";
    const cv::Mat decoded = cv::imdecode(m->data, cv::IMREAD_COLOR);
    ASSERT_FALSE(decoded.empty()) << "not a decodable JPEG (" << m->data.size() << " bytes)";
    EXPECT_EQ(decoded.size(), cv::Size(320, 200)) << "small_pool is 640x400; compressed_scale 0.5";
    EXPECT_GT(cv::mean(decoded)[0] + cv::mean(decoded)[1] + cv::mean(decoded)[2], 30) << "an image, not black";
  }
}

TEST(CompressedImagePublisherConfig, DefaultsAreValidAndEveryBadValueIsNamed) {
  ros_glue::CompressedImagePublisher::Config c;
  EXPECT_TRUE(c.validate("~").empty());
  c.scale = 0;
  c.max_rate_hz = -1;
  c.jpeg_quality = 101;
  const auto problems = c.validate("/d/");
  ASSERT_EQ(problems.size(), 3U);
  EXPECT_EQ(problems[0].rfind("/d/compressed_scale", 0), 0U) << problems[0];
  EXPECT_EQ(problems[1].rfind("/d/compressed_max_rate_hz", 0), 0U) << problems[1];
  EXPECT_EQ(problems[2].rfind("/d/compressed_jpeg_quality", 0), 0U) << problems[2];
  c = {};
  c.scale = 1.5;
  EXPECT_EQ(c.validate("").size(), 1U) << "scale above 1";
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "detector_compressed_test");
  return RUN_ALL_TESTS();
}
