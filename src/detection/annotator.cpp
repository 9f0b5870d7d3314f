// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/annotator.h"

#include <opencv2/imgproc.hpp>

#include <cstdio>

#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {
namespace {

void label(cv::Mat& img, const std::string& text, cv::Point at, double scale, const cv::Scalar& colour) {
  const int thickness = std::max(1, static_cast<int>(scale * 2));
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, thickness, &baseline);
  at.x = std::clamp(at.x, 0, std::max(0, img.cols - size.width));
  at.y = std::clamp(at.y, size.height + 2, img.rows - baseline);
  cv::rectangle(img, at + cv::Point(-2, baseline), at + cv::Point(size.width + 2, -size.height - 2), cv::Scalar(0, 0, 0),
                cv::FILLED);
  cv::putText(img, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, thickness, cv::LINE_AA);
}

}  // namespace

cv::Mat annotate(const cv::Mat& left_bgr, const DetectionResult& result) {
  requireBgr8(left_bgr, "annotate");
  cv::Mat out = left_bgr.clone();
  const double scale = std::max(0.4, left_bgr.cols / 1600.0);
  const int thickness = std::max(1, static_cast<int>(scale * 2));
  char text[160];
  std::snprintf(text, sizeof text, "%s  brightness %.0f%s  %zu object(s)  %.0f ms",
                qualityStatusName(result.quality.status).c_str(), result.quality.mean_brightness,
                result.quality.enhanced ? " (enhanced)" : "", result.objects.size(), result.timings.total_ms);
  label(out, text, {8, static_cast<int>(30 * scale)},
        scale, result.quality.spoiled() ? cv::Scalar(0, 0, 255) : cv::Scalar(255, 255, 255));
  for (const Detection& d : result.objects) {
    const cv::Scalar highlight(255, 255, 0);
    if (d.contour.size() >= 3) cv::polylines(out, std::vector<std::vector<cv::Point>>{d.contour}, true, highlight, thickness);
    cv::rectangle(out, d.roi, cv::Scalar(0, 255, 255), thickness);
    std::snprintf(text, sizeof text, "%s %s %.2f m  r %.2f m", d.colour.c_str(), shapeName(d.shape),
                  d.size_m.maxCoeff(), d.range_m);
    label(out, text, d.roi.tl() + cv::Point(0, -6), scale, highlight);
    std::snprintf(text, sizeof text, "xyz %.2f %.2f %.2f", d.position_m.x(), d.position_m.y(), d.position_m.z());
    label(out, text, cv::Point(d.roi.x, d.roi.br().y + static_cast<int>(24 * scale)), scale, highlight);
  }
  return out;
}

}  // namespace underwater_stereo
