// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/roi_stereo_matcher.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {
namespace {

cv::Matx33d rectifiedIntrinsics(const CameraCalibration& c) {
  return cv::Matx33d(c.P(0, 0), c.P(0, 1), c.P(0, 2), c.P(1, 0), c.P(1, 1), c.P(1, 2), 0, 0, 1);
}

void buildMaps(const CameraCalibration& c, cv::Mat& map_x, cv::Mat& map_y) {
  cv::initUndistortRectifyMap(cv::Mat(c.K), cv::Mat(c.D), cv::Mat(c.R), cv::Mat(rectifiedIntrinsics(c)),
                              cv::Size(c.width, c.height), CV_32FC1, map_x, map_y);
}

}  // namespace

std::vector<std::string> StereoMatchConfig::validate() const {
  std::vector<std::string> p;
  if (!(min_depth_m > 0.05 && min_depth_m < max_depth_m && max_depth_m <= 100)) {
    p.push_back("stereo: need 0.05 < min_depth_m < max_depth_m <= 100, got " + std::to_string(min_depth_m) + " and " +
                std::to_string(max_depth_m));
  }
  if (block_size < 3 || block_size > 11 || block_size % 2 == 0) p.push_back("stereo.block_size must be odd, 3..11");
  if (uniqueness_ratio < 0 || uniqueness_ratio > 50) p.push_back("stereo.uniqueness_ratio must be in [0, 50]");
  if (margin_px < 0 || margin_px > 200) p.push_back("stereo.margin_px must be in [0, 200]");
  if (erode_px < 0 || erode_px > 50) p.push_back("stereo.erode_px must be in [0, 50]");
  if (max_points < 10 || max_points > 1000000) p.push_back("stereo.max_points must be in [10, 1000000]");
  return p;
}

RoiStereoMatcher::RoiStereoMatcher(const StereoCalibration& calibration, const StereoMatchConfig& config)
    : calibration_(calibration), config_(config) {
  std::vector<std::string> problems = calibration_.validate();
  const auto config_problems = config_.validate();
  problems.insert(problems.end(), config_problems.begin(), config_problems.end());
  if (!problems.empty()) throw std::invalid_argument(joinProblems("RoiStereoMatcher", problems));
  buildMaps(calibration_.left, left_map_x_, left_map_y_);
  buildMaps(calibration_.right, right_map_x_, right_map_y_);
  left_r_transposed_ = calibration_.left.R.t();
}

cv::Rect RoiStereoMatcher::rectifiedBox(const cv::Rect& raw_roi) const {
  std::vector<cv::Point2f> corners, rectified;
  // Edges, not just corners: distortion bends the box's sides.
  for (int i = 0; i <= 8; ++i) {
    const float fx = raw_roi.x + raw_roi.width * i / 8.0F, fy = raw_roi.y + raw_roi.height * i / 8.0F;
    corners.insert(corners.end(), {{fx, float(raw_roi.y)}, {fx, float(raw_roi.br().y)}, {float(raw_roi.x), fy},
                                   {float(raw_roi.br().x), fy}});
  }
  const CameraCalibration& c = calibration_.left;
  cv::undistortPoints(corners, rectified, cv::Mat(c.K), cv::Mat(c.D), cv::Mat(c.R), cv::Mat(rectifiedIntrinsics(c)));
  return cv::boundingRect(rectified);
}

RoiPoints RoiStereoMatcher::match(const cv::Mat& left, const cv::Mat& right, const cv::Rect& roi,
                                  const cv::Mat& mask) const {
  const cv::Size size(calibration_.left.width, calibration_.left.height);
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1 || left.size() != size || right.size() != size) {
    throw std::invalid_argument("RoiStereoMatcher::match: left and right must be CV_8UC1 of the calibrated size " +
                                std::to_string(size.width) + "x" + std::to_string(size.height));
  }
  if (roi.empty() || (roi & cv::Rect(cv::Point(), size)) != roi || mask.type() != CV_8UC1 || mask.size() != roi.size()) {
    throw std::invalid_argument("RoiStereoMatcher::match: roi must lie in the image and mask be CV_8UC1 of its size");
  }
  const double f = calibration_.focalPx(), baseline = calibration_.baselineM();
  const double d_min = f * baseline / config_.max_depth_m, d_max = f * baseline / config_.min_depth_m;
  const int min_disparity = static_cast<int>(std::floor(d_min));
  int num_disparities = ((static_cast<int>(std::ceil(d_max)) - min_disparity + 15) / 16) * 16;

  // The band: the object's rectified box plus margin, widened to the left by the largest disparity so the
  // right camera's view of the object is inside the same rectangle.
  const cv::Rect box = rectifiedBox(roi);
  cv::Rect band(box.x - config_.margin_px - min_disparity - num_disparities, box.y - config_.margin_px,
                box.width + 2 * config_.margin_px + min_disparity + num_disparities, box.height + 2 * config_.margin_px);
  band &= cv::Rect(cv::Point(), size);
  RoiPoints out;
  // Near the left edge the band is clipped: only disparities that fit in it can be searched (SGBM needs
  // width > minDisparity + numDisparities, or it fails to allocate).
  const int fitting = ((band.width - min_disparity - config_.block_size - 1) / 16) * 16;
  num_disparities = std::min(num_disparities, fitting);
  if (num_disparities < 16 || band.height < config_.block_size) return out;

  cv::Mat left_band, right_band, mask_band;
  cv::remap(left, left_band, left_map_x_(band), left_map_y_(band), cv::INTER_LINEAR);
  cv::remap(right, right_band, right_map_x_(band), right_map_y_(band), cv::INTER_LINEAR);
  cv::Mat mask_map_x = left_map_x_(band) - roi.x, mask_map_y = left_map_y_(band) - roi.y;
  cv::remap(mask, mask_band, mask_map_x, mask_map_y, cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
  if (config_.erode_px > 0) {
    cv::erode(mask_band, mask_band,
              cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * config_.erode_px + 1, 2 * config_.erode_px + 1)));
  }
  out.mask_pixels = cv::countNonZero(mask_band);
  if (out.mask_pixels == 0) return out;

  const int bs = config_.block_size;
  auto sgbm = cv::StereoSGBM::create(min_disparity, num_disparities, bs, 8 * bs * bs, 32 * bs * bs, 1,
                                     0, config_.uniqueness_ratio, 0, 0, cv::StereoSGBM::MODE_SGBM_3WAY);
  cv::Mat disparity16;
  sgbm->compute(left_band, right_band, disparity16);

  const int step = std::max(1, static_cast<int>(std::sqrt(out.mask_pixels / static_cast<double>(config_.max_points))));
  const double cx = calibration_.left.P(0, 2), cy = calibration_.left.P(1, 2);
  const short invalid_below = static_cast<short>(min_disparity * 16);
  for (int v = 0; v < mask_band.rows; ++v) {
    const auto* m = mask_band.ptr<std::uint8_t>(v);
    const auto* d = disparity16.ptr<short>(v);
    for (int u = 0; u < mask_band.cols; ++u) {
      if (!m[u] || d[u] < invalid_below) continue;
      const double disparity = d[u] / 16.0;
      const double z = f * baseline / disparity;
      if (z < config_.min_depth_m || z > config_.max_depth_m) continue;
      ++out.matched_pixels;
      if ((v % step) != 0 || (u % step) != 0) continue;
      const cv::Vec3d rect((u + band.x - cx) * z / f, (v + band.y - cy) * z / f, z);
      const cv::Vec3d raw = left_r_transposed_ * rect;
      out.points.emplace_back(static_cast<float>(raw[0]), static_cast<float>(raw[1]), static_cast<float>(raw[2]));
    }
  }
  return out;
}

}  // namespace underwater_stereo
