// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/image_quality.h"

#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdint>
#include <stdexcept>

#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {
std::vector<std::string> QualityConfig::validate() const {
  std::vector<std::string> p;
  // Each range as detectorTunables() gives it (detector_tunables_test checks that they agree), then their order.
  if (!(too_dark_below >= 0 && too_dark_below <= 254)) p.push_back("quality.too_dark_below must be in [0, 254]");
  if (!(too_bright_above >= 1 && too_bright_above <= 255)) p.push_back("quality.too_bright_above must be in [1, 255]");
  if (!(too_dark_below < too_bright_above)) {
    p.push_back("quality: too_dark_below must be under too_bright_above, got " + std::to_string(too_dark_below) +
                " and " + std::to_string(too_bright_above));
  }
  if (!(enhance_below >= 0 && enhance_below <= 255)) p.push_back("quality.enhance_below must be in [0, 255]");
  if (dark_pixel_value < 0 || dark_pixel_value > 254) p.push_back("quality.dark_pixel_value must be in [0, 254]");
  if (bright_pixel_value < 1 || bright_pixel_value > 255) p.push_back("quality.bright_pixel_value must be in [1, 255]");
  if (dark_pixel_value >= bright_pixel_value) {
    p.push_back("quality: dark_pixel_value must be under bright_pixel_value, got " + std::to_string(dark_pixel_value) +
                " and " + std::to_string(bright_pixel_value));
  }
  if (!(clahe_clip_limit >= 0.1 && clahe_clip_limit <= 100)) p.push_back("quality.clahe_clip_limit must be in [0.1, 100]");
  if (clahe_tiles < 1 || clahe_tiles > 64) p.push_back("quality.clahe_tiles must be in [1, 64]");
  return p;
}

QualityReport assessQuality(const cv::Mat& bgr, const QualityConfig& config) {
  requireBgr8(bgr, "assessQuality");
  // One pass over the pixels (OpenCV's cvtColor, split, max, compare and countNonZero took five, ~1 ms of a
  // 960x600 frame): the luma is OpenCV's own 8-bit BT.601 conversion (COLOR_BGR2GRAY: 0.299 R + 0.587 G +
  // 0.114 B in 15-bit fixed point, rounded), so the mean is cv::mean's of it; HSV V is the largest channel.
  constexpr int kShift = 15, kB = 3735, kG = 19235, kR = 9798;
  const int dark = config.dark_pixel_value, bright = config.bright_pixel_value;
  std::uint64_t luma_sum = 0, dark_count = 0, bright_count = 0;
  for (int y = 0; y < bgr.rows; ++y) {
    const cv::Vec3b* p = bgr.ptr<cv::Vec3b>(y);
    std::uint32_t row_luma = 0;  // at most 255 x 16.7 M columns: no overflow for any image OpenCV holds per row
    int row_dark = 0, row_bright = 0;
    int x = 0;
#if CV_SIMD
    // Several pixels at a time, the same integer arithmetic: (b, g) and (r, 1) pairs times (kB, kG) and
    // (kR, rounding) summed in 32 bits, as OpenCV's own conversion does.
    const int lanes = cv::v_uint8::nlanes;
    const cv::v_int16 bg_weights = cv::v_reinterpret_as_s16(cv::vx_setall_u32((static_cast<unsigned>(kG) << 16) | kB));
    const cv::v_int16 r1_weights =
        cv::v_reinterpret_as_s16(cv::vx_setall_u32((1u << (kShift - 1)) << 16 | static_cast<unsigned>(kR)));
    const cv::v_int16 one = cv::vx_setall_s16(1);
    cv::v_uint32 luma_acc = cv::vx_setzero_u32();
    int dark_acc = 0, bright_acc = 0;
    if (dark >= 0 && dark <= 255 && bright >= 0 && bright <= 255) {  // else (an unvalidated config) the scalar loop
      const cv::v_uint8 dark_v = cv::vx_setall_u8(static_cast<std::uint8_t>(dark));
      const cv::v_uint8 bright_v = cv::vx_setall_u8(static_cast<std::uint8_t>(bright));
      for (; x <= bgr.cols - lanes; x += lanes) {
        cv::v_uint8 b, g, r;
        cv::v_load_deinterleave(p[x].val, b, g, r);
        cv::v_uint16 b16[2], g16[2], r16[2];
        cv::v_expand(b, b16[0], b16[1]);
        cv::v_expand(g, g16[0], g16[1]);
        cv::v_expand(r, r16[0], r16[1]);
        for (int h = 0; h < 2; ++h) {
          cv::v_int16 bg[2], r1[2];
          cv::v_zip(cv::v_reinterpret_as_s16(b16[h]), cv::v_reinterpret_as_s16(g16[h]), bg[0], bg[1]);
          cv::v_zip(cv::v_reinterpret_as_s16(r16[h]), one, r1[0], r1[1]);
          for (int k = 0; k < 2; ++k) {
            const cv::v_int32 sum = cv::v_dotprod(bg[k], bg_weights) + cv::v_dotprod(r1[k], r1_weights);
            luma_acc += cv::v_reinterpret_as_u32(cv::v_shr<kShift>(sum));
          }
        }
        const cv::v_uint8 v = cv::v_max(b, cv::v_max(g, r));
        dark_acc += static_cast<int>(cv::v_reduce_sum(cv::v_reinterpret_as_u8(v < dark_v) & cv::vx_setall_u8(1)));
        bright_acc += static_cast<int>(cv::v_reduce_sum(cv::v_reinterpret_as_u8(v > bright_v) & cv::vx_setall_u8(1)));
      }
    }
    row_luma += cv::v_reduce_sum(luma_acc);
    row_dark += dark_acc;
    row_bright += bright_acc;
#endif
    for (; x < bgr.cols; ++x) {
      const int b = p[x][0], g = p[x][1], r = p[x][2];
      row_luma += static_cast<std::uint32_t>((b * kB + g * kG + r * kR + (1 << (kShift - 1))) >> kShift);
      const int v = std::max(b, std::max(g, r));
      row_dark += v < dark;
      row_bright += v > bright;
    }
    luma_sum += row_luma;
    dark_count += row_dark;
    bright_count += row_bright;
  }
  QualityReport r;
  const double pixels = static_cast<double>(bgr.total());
  r.mean_brightness = static_cast<double>(luma_sum) / pixels;
  r.dark_fraction = static_cast<double>(dark_count) / pixels;
  r.bright_fraction = static_cast<double>(bright_count) / pixels;
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
