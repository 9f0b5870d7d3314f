// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/compressed_image_publisher.h"

#include <image_transport/image_transport.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sensor_msgs/CompressedImage.h>

#include <algorithm>

namespace underwater_stereo {
namespace ros_glue {

std::vector<std::string> CompressedImagePublisher::Config::validate(const std::string& prefix) const {
  std::vector<std::string> p;
  if (!(scale > 0 && scale <= 1)) {
    p.push_back(prefix + "compressed_scale: must be in (0, 1], got " + std::to_string(scale));
  }
  if (!(max_rate_hz > 0 && max_rate_hz <= 100)) {
    p.push_back(prefix + "compressed_max_rate_hz: must be in (0, 100], got " + std::to_string(max_rate_hz));
  }
  if (jpeg_quality < 1 || jpeg_quality > 100) {
    p.push_back(prefix + "compressed_jpeg_quality: must be 1..100, got " + std::to_string(jpeg_quality));
  }
  return p;
}

CompressedImagePublisher::Config CompressedImagePublisher::readParams(const ros::NodeHandle& nh,
                                                                      std::vector<std::string>& problems) {
  Config c;
  ParamReader params(nh, problems);
  params.optional("compressed_scale", c.scale);
  params.optional("compressed_max_rate_hz", c.max_rate_hz);
  params.optional("compressed_jpeg_quality", c.jpeg_quality);
  const auto invalid = c.validate(nh.getNamespace() + "/");
  problems.insert(problems.end(), invalid.begin(), invalid.end());
  return c;
}

CompressedImagePublisher::CompressedImagePublisher(ros::NodeHandle& nh, const std::string& base_topic,
                                                   const Config& config)
    : config_(config) {
  const auto plugins = image_transport::ImageTransport(nh).getLoadableTransports();
  if (std::find(plugins.begin(), plugins.end(), "image_transport/compressed") == plugins.end()) {
    publisher_ = nh.advertise<sensor_msgs::CompressedImage>(base_topic + "/compressed", 2);
  }
}

bool CompressedImagePublisher::due() {
  if (!publisher_ || publisher_.getNumSubscribers() == 0) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  return ros::SteadyTime::now() >= next_;
}

void CompressedImagePublisher::publish(const std_msgs::Header& header, const cv::Mat& bgr) {
  {
    // A fixed schedule (not "a period after the last one"), so that the average rate is max_rate_hz, whatever the
    // input rate; after a pause it starts afresh instead of catching up.
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::SteadyTime now = ros::SteadyTime::now();
    if (now < next_) return;
    const ros::WallDuration period(1.0 / config_.max_rate_hz);
    next_ = next_ + period < now - period ? now + period : next_ + period;
  }
  cv::Mat small;
  cv::resize(bgr, small, cv::Size(), config_.scale, config_.scale, cv::INTER_AREA);
  sensor_msgs::CompressedImage msg;
  msg.header = header;
  msg.format = "jpeg";
  cv::imencode(".jpg", small, msg.data, {cv::IMWRITE_JPEG_QUALITY, config_.jpeg_quality});
  publisher_.publish(msg);
}

}  // namespace ros_glue
}  // namespace underwater_stereo
