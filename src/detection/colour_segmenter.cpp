// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/colour_segmenter.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
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

const ColourClass* findColourClass(const std::vector<ColourClass>& classes, const std::string& name) {
  const auto it = std::find_if(classes.begin(), classes.end(), [&](const ColourClass& c) { return c.name == name; });
  return it == classes.end() ? nullptr : &*it;
}

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
    if (!(c.min_confidence >= 0 && c.min_confidence <= 1)) p.push_back(n + ".min_confidence must be in [0, 1]");
    if (!(c.min_size_m >= 0 && c.max_size_m >= 0 && (c.max_size_m == 0 || c.max_size_m > c.min_size_m) &&
          c.max_size_m <= 100)) {
      p.push_back(n + ".size_m: need 0 <= min < max <= 100 (0 = no limit)");
    }
  }
  if (!(saturation_floor_factor >= 0 && saturation_floor_factor <= 10)) {
    p.push_back("mask.saturation_floor_factor must be in [0, 10]");
  }
  if (saturation_floor_min < 0 || saturation_floor_min > 255) p.push_back("mask.saturation_floor_min must be in [0, 255]");
  if (blur_px < 0 || blur_px > 51 || (blur_px > 1 && blur_px % 2 == 0)) {
    p.push_back("mask.blur_px must be 0 or 1 (no blur) or odd, in [0, 51]");  // OpenCV's Gaussian kernel is odd
  }
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
  // All classes in one pass (up to 8 at a time): per pixel, the classes its hue, its saturation and its
  // value each admit are bits in three tables; a class holds where all three admit it.
  out.classes.resize(config.classes.size());
  out.any = cv::Mat::zeros(bgr.size(), CV_8UC1);
  cv::Mat bits(hsv.size(), CV_8UC1), bit;
  for (std::size_t first = 0; first < config.classes.size(); first += 8) {
    const std::size_t count = std::min<std::size_t>(8, config.classes.size() - first);
    std::uint8_t hue_bits[256] = {}, saturation_bits[256] = {}, value_bits[256] = {};
    for (std::size_t k = 0; k < count; ++k) {
      const ColourClass& c = config.classes[first + k];
      const auto flag = static_cast<std::uint8_t>(1U << k);
      int s_min = c.saturation_min;
      if (config.saturation_floor_factor > 0) {
        const int adaptive = static_cast<int>(std::lround(config.saturation_floor_factor * out.saturation_median));
        s_min = std::min(s_min, std::max(config.saturation_floor_min, adaptive));
      }
      for (int h = 0; h < 180; ++h) {
        if (c.admitsHue(h)) hue_bits[h] |= flag;
      }
      for (int v = s_min; v <= c.saturation_max; ++v) saturation_bits[v] |= flag;
      for (int v = c.value_min; v <= c.value_max; ++v) value_bits[v] |= flag;
    }
    for (int y = 0; y < hsv.rows; ++y) {
      const auto* p = hsv.ptr<std::uint8_t>(y);
      auto* b = bits.ptr<std::uint8_t>(y);
      for (int x = 0; x < hsv.cols; ++x, p += 3) b[x] = hue_bits[p[0]] & saturation_bits[p[1]] & value_bits[p[2]];
    }
    for (std::size_t k = 0; k < count; ++k) {
      cv::bitwise_and(bits, cv::Scalar(1U << k), bit);
      cv::compare(bit, 0, out.classes[first + k], cv::CMP_NE);
    }
    out.any.setTo(255, bits);
  }
  auto kernel = [](int size) {
    return size > 1 ? cv::getStructuringElement(cv::MORPH_RECT, cv::Size(size, size)) : cv::Mat();
  };
  if (config.open_kernel_px > 1) cv::morphologyEx(out.any, out.any, cv::MORPH_OPEN, kernel(config.open_kernel_px));
  if (config.close_kernel_px > 1) cv::morphologyEx(out.any, out.any, cv::MORPH_CLOSE, kernel(config.close_kernel_px));
  return out;
}

}  // namespace underwater_stereo
