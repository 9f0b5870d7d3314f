// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/image_quality.h"

#include <opencv2/imgproc.hpp>

#include <stdexcept>

#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {
std::vector<std::string> QualityConfig::validate() const {
  std::vector<std::string> p;
  if (!(too_dark_below >= 0 && too_dark_below < too_bright_above && too_bright_above <= 255)) {
    p.push_back("quality: need 0 <= too_dark_below < too_bright_above <= 255, got " + std::to_string(too_dark_below) +
                " and " + std::to_string(too_bright_above));
  }
  if (!(enhance_below >= 0 && enhance_below <= 255)) p.push_back("quality.enhance_below must be in [0, 255]");
  if (dark_pixel_value < 0 || dark_pixel_value >= bright_pixel_value || bright_pixel_value > 255) {
    p.push_back("quality: need 0 <= dark_pixel_value < bright_pixel_value <= 255");
  }
  if (!(clahe_clip_limit > 0 && clahe_clip_limit <= 100)) p.push_back("quality.clahe_clip_limit must be in (0, 100]");
  if (clahe_tiles < 1 || clahe_tiles > 64) p.push_back("quality.clahe_tiles must be in [1, 64]");
  return p;
}

QualityReport assessQuality(const cv::Mat& bgr, const QualityConfig& config) {
  requireBgr8(bgr, "assessQuality");
  cv::Mat luma;
  cv::cvtColor(bgr, luma, cv::COLOR_BGR2GRAY);  // OpenCV uses the BT.601 weights 0.299 R + 0.587 G + 0.114 B
  // HSV V is the largest channel.
  cv::Mat channels[3], value;
  cv::split(bgr, channels);
  cv::max(channels[0], channels[1], value);
  cv::max(value, channels[2], value);
  QualityReport r;
  r.mean_brightness = cv::mean(luma)[0];
  const double pixels = static_cast<double>(bgr.total());
  r.dark_fraction = cv::countNonZero(value < config.dark_pixel_value) / pixels;
  r.bright_fraction = cv::countNonZero(value > config.bright_pixel_value) / pixels;
  if (r.mean_brightness < config.too_dark_below) r.status = QualityStatus::kTooDark;
  else if (r.mean_brightness > config.too_bright_above) r.status = QualityStatus::kTooBright;
  r.enhanced = !r.spoiled() && r.mean_brightness < config.enhance_below;
  return r;
}

cv::Mat enhanceContrast(const cv::Mat& bgr, const QualityConfig& config) {
  requireBgr8(bgr, "enhanceContrast");
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  cv::Mat channels[3];
  cv::split(hsv, channels);
  cv::createCLAHE(config.clahe_clip_limit, cv::Size(config.clahe_tiles, config.clahe_tiles))->apply(channels[2], channels[2]);
  cv::merge(channels, 3, hsv);
  cv::Mat out;
  cv::cvtColor(hsv, out, cv::COLOR_HSV2BGR);
  return out;
}

std::string qualityStatusName(QualityStatus status) {
  switch (status) {
    case QualityStatus::kOk: return "OK";
    case QualityStatus::kTooDark: return "TOO_DARK";
    case QualityStatus::kTooBright: return "TOO_BRIGHT";
  }
  return "UNKNOWN";
}

}  // namespace underwater_stereo
