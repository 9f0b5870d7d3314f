// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/auto_exposure.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace underwater_stereo {

ExposureSync exposureSyncFromName(const std::string& name) {
  if (name == "independent") return ExposureSync::kIndependent;
  if (name == "master_slave") return ExposureSync::kMasterSlave;
  if (name == "fixed") return ExposureSync::kFixed;
  throw std::invalid_argument("exposure_sync '" + name + "' is not independent, master_slave or fixed");
}

std::string exposureSyncName(ExposureSync sync) {
  switch (sync) {
    case ExposureSync::kIndependent: return "independent";
    case ExposureSync::kMasterSlave: return "master_slave";
    case ExposureSync::kFixed: break;
  }
  return "fixed";
}

std::vector<std::string> AutoExposureSettings::validate(const std::string& name) const {
  std::vector<std::string> p;
  if (!(target >= 0.05 && target <= 0.95)) p.push_back(name + "auto_target must be in [0.05, 0.95]");
  if (!(exposure_min_us > 0 && exposure_min_us < exposure_max_us)) {
    p.push_back(name + "exposure_auto_min_us, exposure_auto_max_us: need 0 < min < max");
  }
  if (!(gain_min_db >= 0 && gain_min_db <= gain_max_db && gain_max_db <= 48)) {
    p.push_back(name + "gain_auto_min_db, gain_auto_max_db: need 0 <= min <= max <= 48");
  }
  if (!(deadband >= 0 && deadband < 0.5)) p.push_back(name + "auto_deadband must be in [0, 0.5)");
  if (!(max_step > 1 && max_step <= 8)) p.push_back(name + "auto_max_step must be in (1, 8]");
  const AutoRoi& r = roi;
  if (!(r.x >= 0 && r.y >= 0 && r.width > 0 && r.height > 0 && r.x + r.width <= 1 + 1e-9 &&
        r.y + r.height <= 1 + 1e-9)) {
    p.push_back(name + "auto_roi [x, y, width, height] must be shares of the image inside [0, 1] with width, "
                       "height > 0");
  }
  return p;
}

double meanBrightness(const cv::Mat& image, const AutoRoi& roi) {
  if (image.empty() || image.depth() != CV_8U) {
    throw std::invalid_argument("meanBrightness: need a non-empty 8-bit image");
  }
  const int x0 = static_cast<int>(std::lround(roi.x * image.cols));
  const int y0 = static_cast<int>(std::lround(roi.y * image.rows));
  const int x1 = std::min(image.cols, static_cast<int>(std::lround((roi.x + roi.width) * image.cols)));
  const int y1 = std::min(image.rows, static_cast<int>(std::lround((roi.y + roi.height) * image.rows)));
  if (roi.x < 0 || roi.y < 0 || x1 <= x0 || y1 <= y0) {
    throw std::invalid_argument("meanBrightness: the ROI is outside the image or empty");
  }
  constexpr int kStride = 4;
  const int channels = image.channels();
  std::uint64_t sum = 0, n = 0;
  for (int y = y0; y < y1; y += kStride) {
    const std::uint8_t* row = image.ptr<std::uint8_t>(y);
    for (int x = x0; x < x1; x += kStride) {
      for (int c = 0; c < channels; ++c) sum += row[x * channels + c];
      n += static_cast<std::uint64_t>(channels);
    }
  }
  return static_cast<double>(sum) / (255.0 * static_cast<double>(n));
}

Exposure nextExposure(const AutoExposureSettings& s, double measured, const Exposure& taken) {
  const double m = std::max(measured, 1.0 / 255.0);  // a black frame still asks for more light
  if (std::abs(m / s.target - 1.0) < s.deadband) return taken;
  const double ratio = std::clamp(s.target / m, 1.0 / s.max_step, s.max_step);
  const double product = taken.exposure_us * std::pow(10.0, taken.gain_db / 20.0) * ratio;
  Exposure next;
  next.exposure_us = std::clamp(product / std::pow(10.0, s.gain_min_db / 20.0), s.exposure_min_us, s.exposure_max_us);
  next.gain_db = std::clamp(20.0 * std::log10(product / next.exposure_us), s.gain_min_db, s.gain_max_db);
  return next;
}

}  // namespace underwater_stereo
