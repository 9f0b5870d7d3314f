// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/stereo_input.h"

#include <cv_bridge/cv_bridge.h>
#include <sensor_msgs/image_encodings.h>

#include <cmath>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/detection/image_checks.h"
#include "underwater_stereo/ros_glue/calibration_conversions.h"

namespace underwater_stereo {
namespace ros_glue {
namespace {

std::string sizeOf(std::uint32_t width, std::uint32_t height) {
  return std::to_string(width) + "x" + std::to_string(height);
}

/// The camera_info topic beside an image topic (".../image_raw" -> ".../camera_info").
std::string topicOfInfo(const std::string& image_topic) {
  const auto slash = image_topic.rfind('/');
  return (slash == std::string::npos ? std::string() : image_topic.substr(0, slash + 1)) + "camera_info";
}

RawFrame toRawFrame(const sensor_msgs::Image& image, const std::string& topic, double search_scale) {
  const std::string size_problem = imageSizeProblem(image.width, image.height, search_scale);
  if (!size_problem.empty()) throw std::invalid_argument(topic + ": " + size_problem);
  if (!acceptedEncoding(image.encoding)) {
    throw std::invalid_argument(topic + ": encoding '" + image.encoding +
                                "' is not accepted (bayer_rggb8/bggr8/gbrg8/grbg8, bgr8, rgb8, mono8)");
  }
  const std::size_t row_bytes =
      static_cast<std::size_t>(image.width) * sensor_msgs::image_encodings::numChannels(image.encoding);
  if (image.step < row_bytes) {
    throw std::invalid_argument(topic + ": step " + std::to_string(image.step) + " is below the " +
                                std::to_string(row_bytes) + " bytes of a " + sizeOf(image.width, image.height) + " " +
                                image.encoding + " row");
  }
  if (image.data.size() != static_cast<std::size_t>(image.step) * image.height) {
    throw std::invalid_argument(topic + ": data has " + std::to_string(image.data.size()) + " bytes, step x height = " +
                                std::to_string(image.step) + " x " + std::to_string(image.height) + " needs " +
                                std::to_string(static_cast<std::size_t>(image.step) * image.height));
  }
  try {
    // rgb8 is converted; everything else shares the message's buffer (zero-copy within a nodelet manager; the
    // caller keeps the message): Bayer mosaics are demosaiced by the detector only where it needs colour.
    if (image.encoding == sensor_msgs::image_encodings::RGB8) {
      return RawFrame(cv_bridge::toCvCopy(image, sensor_msgs::image_encodings::BGR8)->image);
    }
    return RawFrame(cv_bridge::toCvShare(image, boost::shared_ptr<const void>())->image, pixelLayoutOf(image.encoding));
  } catch (const cv_bridge::Exception& e) {
    throw std::invalid_argument(topic + ": cannot read '" + image.encoding + "': " + e.what());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(topic + ": " + e.what());
  }
}

CameraCalibration toCalibration(const sensor_msgs::CameraInfo& info, const sensor_msgs::Image& image,
                                const std::string& topic) {
  if (info.width != image.width || info.height != image.height) {
    throw std::invalid_argument(topic + ": image is " + sizeOf(image.width, image.height) + " but its camera_info is " +
                                sizeOf(info.width, info.height));
  }
  // Binning or a region of interest would need the calibration scaled and shifted; not supported, so refused
  // rather than giving wrong positions.
  const auto& roi = info.roi;
  const bool full_roi = (roi.width == 0 && roi.height == 0 && roi.x_offset == 0 && roi.y_offset == 0) ||
                        (roi.x_offset == 0 && roi.y_offset == 0 && roi.width == info.width && roi.height == info.height);
  if (info.binning_x > 1 || info.binning_y > 1 || !full_roi) {
    throw std::invalid_argument(topicOfInfo(topic) + ": binning " + std::to_string(info.binning_x) + "x" +
                                std::to_string(info.binning_y) + ", roi " + std::to_string(roi.width) + "x" +
                                std::to_string(roi.height) + "+" + std::to_string(roi.x_offset) + "+" +
                                std::to_string(roi.y_offset) +
                                ": only full-resolution images are supported (binning 0 or 1, roi empty or the whole image)");
  }
  try {
    return fromCameraInfo(info);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(topicOfInfo(topic) + ": " + e.what());
  }
}

}  // namespace

bool acceptedEncoding(const std::string& e) {
  // The detector reads these as they are; rgb8 is converted to bgr8.
  return e == sensor_msgs::image_encodings::RGB8 || layoutOfEncoding(e).has_value();
}

StereoInput toStereoInput(const sensor_msgs::Image& left, const sensor_msgs::CameraInfo& left_info,
                          const sensor_msgs::Image& right, const sensor_msgs::CameraInfo& right_info,
                          const std::string& left_topic, const std::string& right_topic, double max_skew_s,
                          double search_scale) {
  const double skew = std::abs(left.header.stamp.toSec() - right.header.stamp.toSec());
  if (skew > max_skew_s) {
    throw std::invalid_argument(left_topic + " and " + right_topic + ": stamps " + std::to_string(skew) +
                                " s apart (at most " + std::to_string(max_skew_s) + " s)");
  }
  StereoInput in;
  in.left = toRawFrame(left, left_topic, search_scale);
  in.right = toRawFrame(right, right_topic, search_scale);
  if (in.left.size() != in.right.size()) {
    throw std::invalid_argument(left_topic + " is " + sizeOf(left.width, left.height) + " but " + right_topic + " is " +
                                sizeOf(right.width, right.height));
  }
  in.calibration.left = toCalibration(left_info, left, left_topic);
  in.calibration.right = toCalibration(right_info, right, right_topic);
  const auto problems = in.calibration.validate();
  if (!problems.empty()) {
    throw std::invalid_argument(joinProblems("camera_info of " + left_topic + " / " + right_topic, problems));
  }
  return in;
}

}  // namespace ros_glue
}  // namespace underwater_stereo
