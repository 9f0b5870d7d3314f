// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/blob_proposals.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {
namespace {

/// Opening that removes single-pixel specks of saliency (sensor noise, JPEG blocks) before cutting regions.
constexpr int kOpenPx = 3;
/// Width of the ring of water around a region that its contrast is compared with.
constexpr int kRingPx = 3;

cv::Mat openKernel() { return cv::getStructuringElement(cv::MORPH_RECT, cv::Size(kOpenPx, kOpenPx)); }

std::vector<float> describe(const cv::Mat& bgr, const cv::Mat& hsv, const WaterContrast& wc, const BlobProposal& b) {
  const cv::Rect frame(0, 0, bgr.cols, bgr.rows);
  const cv::Rect outer = (b.roi + cv::Size(2 * kRingPx, 2 * kRingPx) - cv::Point(kRingPx, kRingPx)) & frame;
  cv::Mat inside = cv::Mat::zeros(outer.size(), CV_8UC1);
  b.mask.copyTo(inside(b.roi - outer.tl()));
  cv::Mat ring;
  cv::dilate(inside, ring, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * kRingPx + 1, 2 * kRingPx + 1)));
  ring &= ~inside;
  cv::Scalar f_mean, f_std, c_mean, c_std, r_mean, r_std, s_mean, s_std;
  cv::meanStdDev(wc.contrast(outer), f_mean, f_std, inside);
  cv::meanStdDev(wc.chroma(outer), c_mean, c_std, inside);
  if (cv::countNonZero(ring) > 0) {
    cv::meanStdDev(wc.contrast(outer), r_mean, r_std, ring);
  } else {
    r_mean = f_mean;
  }
  cv::meanStdDev(wc.saliency[static_cast<int>(b.kind)](outer), s_mean, s_std, inside);
  const cv::Scalar raw = cv::mean(bgr(outer), inside);
  const cv::Scalar hsv_mean = cv::mean(hsv(outer), inside);
  const double raw_sum = raw[0] + raw[1] + raw[2] + 1e-3;
  std::vector<cv::Point> hull;
  cv::convexHull(b.contour, hull);
  const double hull_area = std::max(cv::contourArea(hull), 1.0);
  const double perimeter = std::max(cv::arcLength(b.contour, true), 1.0);
  // Hue is circular and HSV's mean hue is not: hue enters as the direction of the mean colour's chroma.
  const double hue = std::atan2(std::sqrt(3.0) * (raw[1] - raw[0]), 2 * raw[2] - raw[1] - raw[0]);
  const double image_area = static_cast<double>(bgr.total());
  return {static_cast<float>(f_mean[0]), static_cast<float>(f_mean[1]), static_cast<float>(f_mean[2]),
          static_cast<float>(c_mean[0]), static_cast<float>(c_mean[1]), static_cast<float>(c_mean[2]),
          static_cast<float>(f_mean[0] - r_mean[0]), static_cast<float>(f_mean[1] - r_mean[1]),
          static_cast<float>(f_mean[2] - r_mean[2]),
          static_cast<float>(f_std[0]), static_cast<float>(f_std[1]), static_cast<float>(f_std[2]),
          static_cast<float>(raw[0] / raw_sum), static_cast<float>(raw[1] / raw_sum), static_cast<float>(raw[2] / raw_sum),
          static_cast<float>(std::log(b.area_px / image_area)),
          static_cast<float>(b.area_px / std::max(1, b.roi.area())),
          static_cast<float>(b.roi.width / std::max(1.0, double(b.roi.height))),
          static_cast<float>(b.area_px / hull_area),
          static_cast<float>(4 * M_PI * b.area_px / (perimeter * perimeter)),
          static_cast<float>(std::log(b.level)), static_cast<float>(b.kind == SaliencyKind::kFull ? 1 : 0),
          static_cast<float>(std::log(s_mean[0] + 1)),
          static_cast<float>(hsv_mean[1] / 255.0), static_cast<float>(raw_sum / (3 * 255.0)),
          static_cast<float>(std::cos(hue)), static_cast<float>(std::sin(hue))};
}

}  // namespace

const std::vector<std::string>& blobFeatureNames() {
  static const std::vector<std::string> names{
      "contrast_b", "contrast_g", "contrast_r", "chroma_b", "chroma_g", "chroma_r", "edge_b", "edge_g", "edge_r",
      "texture_b", "texture_g", "texture_r", "chromaticity_b", "chromaticity_g", "chromaticity_r", "log_area_fraction",
      "fill", "aspect", "solidity", "circularity", "log_level", "full_saliency", "log_saliency", "saturation",
      "brightness", "hue_cos", "hue_sin"};
  return names;
}

std::vector<std::string> ProposalConfig::validate() const {
  std::vector<std::string> p;
  if (levels.empty() || levels.size() > 16) p.push_back("proposals.levels: 1 to 16 levels");
  for (double l : levels) {
    if (!(l > 0 && l <= 1000)) p.push_back("proposals.levels: each in (0, 1000]");
  }
  if (!(min_area_px >= 1 && min_area_px < max_area_px)) p.push_back("proposals: need 1 <= min_area_px < max_area_px");
  if (max_proposals < 1 || max_proposals > 10000) p.push_back("proposals.max_proposals must be in [1, 10000]");
  return p;
}

cv::Mat salientMask(const WaterContrast& contrast, SaliencyKind kind, double level) {
  cv::Mat mask;
  cv::compare(contrast.saliency[static_cast<int>(kind)], level, mask, cv::CMP_GT);
  cv::morphologyEx(mask, mask, cv::MORPH_OPEN, openKernel());
  return mask;
}

std::vector<BlobProposal> proposeBlobs(const cv::Mat& bgr, const WaterContrast& contrast, const ProposalConfig& config) {
  requireBgr8(bgr, "proposeBlobs");
  if (contrast.contrast.size() != bgr.size()) throw std::invalid_argument("proposeBlobs: contrast and image sizes differ");
  const auto problems = config.validate();
  if (!problems.empty()) throw std::invalid_argument("proposeBlobs: " + problems.front());
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  std::vector<BlobProposal> out;
  for (const SaliencyKind kind : {SaliencyKind::kChroma, SaliencyKind::kFull}) {
    for (const double level : config.levels) {
      std::vector<std::vector<cv::Point>> contours;
      cv::findContours(salientMask(contrast, kind, level), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
      for (auto& contour : contours) {
        const double area = cv::contourArea(contour);
        if (area < config.min_area_px || area > config.max_area_px || contour.size() < 3) continue;
        BlobProposal b;
        b.roi = cv::boundingRect(contour);
        b.mask = cv::Mat::zeros(b.roi.size(), CV_8UC1);
        cv::drawContours(b.mask, std::vector<std::vector<cv::Point>>{contour}, 0, 255, cv::FILLED, cv::LINE_8,
                         cv::noArray(), 0, -b.roi.tl());
        b.area_px = area;
        b.kind = kind;
        b.level = level;
        b.contour = std::move(contour);
        out.push_back(std::move(b));
      }
    }
  }
  if (out.size() > static_cast<std::size_t>(config.max_proposals)) {
    // The most salient (highest level, then largest) first.
    std::stable_sort(out.begin(), out.end(), [](const BlobProposal& a, const BlobProposal& b) {
      return a.level != b.level ? a.level > b.level : a.area_px > b.area_px;
    });
    out.resize(config.max_proposals);
  }
  for (BlobProposal& b : out) b.features = describe(bgr, hsv, contrast, b);
  return out;
}

}  // namespace underwater_stereo
