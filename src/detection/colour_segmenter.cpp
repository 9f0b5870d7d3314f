// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/colour_segmenter.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {
namespace {

void checkRange(std::vector<std::string>& p, const std::string& what, int lo, int hi, int max) {
  if (lo < 0 || lo > max || hi < 0 || hi > max) {
    p.push_back(what + ": [" + std::to_string(lo) + ", " + std::to_string(hi) + "] must lie in [0, " +
                std::to_string(max) + "]");
  }
}

/// Median of one channel of an 8-bit 3-channel image.
int channelMedian(const cv::Mat& image, int channel) {
  const int channels[] = {channel};
  const int bins[] = {256};
  const float range[] = {0, 256};
  const float* ranges[] = {range};
  cv::Mat hist;
  cv::calcHist(&image, 1, channels, cv::Mat(), hist, 1, bins, ranges);
  const double limit = 0.5 * static_cast<double>(image.total());
  double count = 0;
  for (int v = 0; v < 256; ++v) {
    count += hist.at<float>(v);
    if (count >= limit) return v;
  }
  return 255;
}

}  // namespace

std::vector<std::string> ColourMaskConfig::validate() const {
  std::vector<std::string> p;
  if (classes.empty()) p.push_back("colours: at least one designated colour is needed");
  for (std::size_t i = 0; i < classes.size(); ++i) {
    const ColourClass& c = classes[i];
    const std::string n = "colours[" + std::to_string(i) + "] (" + c.name + ")";
    if (c.name.empty()) p.push_back(n + ": name is empty");
    for (std::size_t j = 0; j < i; ++j) {
      if (classes[j].name == c.name) p.push_back(n + ": name is used twice");
    }
    checkRange(p, n + ".hue", c.hue_min, c.hue_max, 179);
    checkRange(p, n + ".saturation", c.saturation_min, c.saturation_max, 255);
    checkRange(p, n + ".value", c.value_min, c.value_max, 255);
    if (c.saturation_min > c.saturation_max) p.push_back(n + ".saturation: min > max");
    if (c.value_min > c.value_max) p.push_back(n + ".value: min > max");
    if (!(c.min_contrast >= 0 && c.min_contrast <= 10)) p.push_back(n + ".min_contrast must be in [0, 10]");
  }
  if (!(saturation_floor_factor >= 0 && saturation_floor_factor <= 10)) {
    p.push_back("mask.saturation_floor_factor must be in [0, 10]");
  }
  if (saturation_floor_min < 0 || saturation_floor_min > 255) p.push_back("mask.saturation_floor_min must be in [0, 255]");
  if (blur_px < 0 || blur_px > 51) p.push_back("mask.blur_px must be in [0, 51]");
  if (open_kernel_px < 0 || open_kernel_px > 101) p.push_back("mask.open_kernel_px must be in [0, 101]");
  if (close_kernel_px < 0 || close_kernel_px > 101) p.push_back("mask.close_kernel_px must be in [0, 101]");
  return p;
}

cv::Scalar greyWorldGains(const cv::Mat& bgr) {
  requireBgr8(bgr, "greyWorldGains");
  const cv::Scalar mean = cv::mean(bgr);
  const double grey = (mean[0] + mean[1] + mean[2]) / 3.0;
  return cv::Scalar(grey / std::max(mean[0], 1.0), grey / std::max(mean[1], 1.0), grey / std::max(mean[2], 1.0));
}

cv::Mat applyGains(const cv::Mat& bgr, const cv::Scalar& gains) {
  requireBgr8(bgr, "applyGains");
  // Per plane: convertTo's scaling is vectorised, cv::multiply by a Scalar on 8-bit images is not (4x slower).
  cv::Mat channels[3];
  cv::split(bgr, channels);
  for (int c = 0; c < 3; ++c) channels[c].convertTo(channels[c], CV_8U, gains[c]);
  cv::Mat out;
  cv::merge(channels, 3, out);
  return out;
}

cv::Mat greyWorld(const cv::Mat& bgr) { return applyGains(bgr, greyWorldGains(bgr)); }

ColourMasks colourMasks(const cv::Mat& bgr, const ColourMaskConfig& config, int saturation_median) {
  requireBgr8(bgr, "colourMasks");
  cv::Mat hsv;
  if (config.blur_px > 1) {
    cv::GaussianBlur(bgr, hsv, cv::Size(config.blur_px, config.blur_px), 0);  // 5x faster than a box blur
    cv::cvtColor(hsv, hsv, cv::COLOR_BGR2HSV);
  } else {
    cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  }
  ColourMasks out;
  out.saturation_median = saturation_median >= 0 ? saturation_median : channelMedian(hsv, 1);
  // inRange is single-threaded: the classes are thresholded in parallel.
  out.classes.resize(config.classes.size());
  cv::parallel_for_(cv::Range(0, static_cast<int>(config.classes.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      const ColourClass& c = config.classes[i];
      cv::Mat& mask = out.classes[i];
      int s_min = c.saturation_min;
      if (config.saturation_floor_factor > 0) {
        const int adaptive = static_cast<int>(std::lround(config.saturation_floor_factor * out.saturation_median));
        s_min = std::min(s_min, std::max(config.saturation_floor_min, adaptive));
      }
      const cv::Scalar lo_sv(0, s_min, c.value_min), hi_sv(0, c.saturation_max, c.value_max);
      if (c.hue_min <= c.hue_max) {
        cv::inRange(hsv, cv::Scalar(c.hue_min, lo_sv[1], lo_sv[2]), cv::Scalar(c.hue_max, hi_sv[1], hi_sv[2]), mask);
      } else {  // wraps through 0 (red)
        cv::Mat upper;
        cv::inRange(hsv, cv::Scalar(c.hue_min, lo_sv[1], lo_sv[2]), cv::Scalar(179, hi_sv[1], hi_sv[2]), upper);
        cv::inRange(hsv, cv::Scalar(0, lo_sv[1], lo_sv[2]), cv::Scalar(c.hue_max, hi_sv[1], hi_sv[2]), mask);
        mask |= upper;
      }
    }
  });
  out.any = cv::Mat::zeros(bgr.size(), CV_8UC1);
  for (const cv::Mat& mask : out.classes) out.any |= mask;
  auto kernel = [](int size) {
    return size > 1 ? cv::getStructuringElement(cv::MORPH_RECT, cv::Size(size, size)) : cv::Mat();
  };
  if (config.open_kernel_px > 1) cv::morphologyEx(out.any, out.any, cv::MORPH_OPEN, kernel(config.open_kernel_px));
  if (config.close_kernel_px > 1) cv::morphologyEx(out.any, out.any, cv::MORPH_CLOSE, kernel(config.close_kernel_px));
  return out;
}

}  // namespace underwater_stereo
