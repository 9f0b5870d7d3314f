// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A tether-sized copy of an image topic: `<base>/compressed` (sensor_msgs/CompressedImage, JPEG), scaled
/// down and rate-limited, made only while someone subscribes. Debian 12 has no compressed_image_transport plugin;
/// this is the topic and format a topside image_transport subscriber with that plugin reads.

#include <opencv2/core.hpp>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/time.h>
#include <std_msgs/Header.h>

#include <mutex>
#include <string>
#include <vector>

#include "underwater_stereo/ros_glue/param_reader.h"

namespace underwater_stereo {
namespace ros_glue {

class CompressedImagePublisher {
 public:
  struct Config {
    double scale = 0.5;         ///< (0, 1]: size of the JPEG relative to the image
    double max_rate_hz = 5.0;   ///< (0, 100]: at most this many messages per second (evenly picked)
    int jpeg_quality = 80;      ///< 1..100

    /// Every problem, each naming its parameter (`prefix` + name); empty when valid.
    std::vector<std::string> validate(const std::string& prefix) const;
  };

  /// Reads `compressed_scale`, `compressed_max_rate_hz` and `compressed_jpeg_quality` from `nh` (private
  /// parameters), appending every problem (wrong type, out of range) to `problems`.
  static Config readParams(const ros::NodeHandle& nh, std::vector<std::string>& problems);

  /// Advertises `<base_topic>/compressed` on `nh`; if image_transport's own compressed plugin is loadable, it
  /// already publishes that topic and this publisher stays silent.
  CompressedImagePublisher(ros::NodeHandle& nh, const std::string& base_topic, const Config& config);

  /// Whether an image handed over now would be published (someone subscribes and the rate limit allows it).
  /// Cheap: call it before making the image. Thread-safe.
  bool due();

  /// Scales, encodes and publishes a BGR image (CV_8UC3) with `header` if due(); the caller checked due().
  /// @throw cv::Exception when the image cannot be encoded.
  void publish(const std_msgs::Header& header, const cv::Mat& bgr);

 private:
  Config config_;
  ros::Publisher publisher_;
  std::mutex mutex_;
  ros::SteadyTime next_;  ///< earliest time of the next message
};

}  // namespace ros_glue
}  // namespace underwater_stereo
