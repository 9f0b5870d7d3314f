// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/candidate_finder.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {
namespace {

/// Fills `candidate` from its contour and the colour mask it belongs to.
bool describe(const cv::Mat& bgr, const cv::Mat& colour_mask, std::vector<cv::Point> contour, int colour_index,
              const CandidateConfig& config, Candidate& out) {
  const double area = cv::contourArea(contour);
  if (area < config.min_area_px || area > config.max_area_px || contour.size() < 3) return false;
  out.roi = cv::boundingRect(contour);
  cv::Mat filled = cv::Mat::zeros(out.roi.size(), CV_8UC1);
  cv::drawContours(filled, std::vector<std::vector<cv::Point>>{contour}, 0, 255, cv::FILLED, cv::LINE_8, cv::noArray(),
                   0, -out.roi.tl());
  const int inside = cv::countNonZero(filled);
  out.mask = filled & colour_mask(out.roi);
  out.colour_fraction = inside > 0 ? cv::countNonZero(out.mask) / static_cast<double>(inside) : 0.0;
  if (out.colour_fraction < config.min_colour_fraction) return false;
  out.colour_index = colour_index;
  out.area_px = area;
  out.outline = classifyOutline(contour);
  out.mean_bgr = cv::mean(bgr(out.roi), out.mask);
  out.contour = std::move(contour);
  return true;
}

std::vector<std::vector<cv::Point>> externalContours(const cv::Mat& binary) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(binary, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  return contours;
}

}  // namespace

std::vector<std::string> CandidateConfig::validate() const {
  std::vector<std::string> p;
  if (fixed_threshold < 0 || fixed_threshold > 255) p.push_back("candidates.fixed_threshold must be in [0, 255]");
  if (blur_kernel_px < 1 || blur_kernel_px % 2 == 0 || blur_kernel_px > 51) {
    p.push_back("candidates.blur_kernel_px must be odd, in [1, 51]");
  }
  if (!(min_area_px >= 1 && min_area_px < max_area_px)) {
    p.push_back("candidates: need 1 <= min_area_px < max_area_px");
  }
  if (!(min_colour_fraction > 0 && min_colour_fraction <= 1)) {
    p.push_back("candidates.min_colour_fraction must be in (0, 1]");
  }
  if (!(max_candidates >= 1 && max_candidates <= 1000)) p.push_back("candidates.max_candidates must be in [1, 1000]");
  return p;
}

std::string classifyOutline(const std::vector<cv::Point>& contour) {
  if (contour.size() < 3) throw std::invalid_argument("classifyOutline: a contour needs at least 3 points");
  const double perimeter = cv::arcLength(contour, true);
  const double area = cv::contourArea(contour);
  std::vector<cv::Point> poly;
  cv::approxPolyDP(contour, poly, 0.03 * perimeter, true);
  if (poly.size() == 3) return "triangle";
  if (poly.size() == 4 && cv::isContourConvex(poly)) {
    // Rectangle when the quadrilateral fills its minimum-area rectangle.
    const cv::RotatedRect box = cv::minAreaRect(contour);
    if (area > 0.85 * box.size.area()) return "rectangle";
  }
  if (contour.size() >= 5 && area > 0) {
    const cv::RotatedRect e = cv::fitEllipse(contour);
    const double ellipse_area = M_PI * e.size.width * e.size.height / 4.0;
    if (std::abs(ellipse_area - area) < 0.06 * area) {
      const double ratio = std::min(e.size.width, e.size.height) / std::max(e.size.width, e.size.height);
      return ratio > 0.88 ? "circle" : "ellipse";
    }
  }
  return "polygon";
}

std::vector<Candidate> findCandidates(const cv::Mat& bgr, const std::vector<cv::Mat>& masks,
                                      const CandidateConfig& config) {
  requireBgr8(bgr, "findCandidates");
  for (const cv::Mat& m : masks) {
    if (m.size() != bgr.size() || m.type() != CV_8UC1) {
      throw std::invalid_argument("findCandidates: each colour mask must be CV_8UC1 of the image's size");
    }
  }
  std::vector<Candidate> found;
  if (config.source == ContourSource::kColourMask) {
    for (std::size_t c = 0; c < masks.size(); ++c) {
      for (auto& contour : externalContours(masks[c])) {
        Candidate candidate;
        if (describe(bgr, masks[c], std::move(contour), static_cast<int>(c), config, candidate)) {
          found.push_back(std::move(candidate));
        }
      }
    }
  } else {
    cv::Mat grey, binary;
    cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
    cv::GaussianBlur(grey, grey, cv::Size(config.blur_kernel_px, config.blur_kernel_px), 0);
    const int type = (config.dark_objects ? cv::THRESH_BINARY_INV : cv::THRESH_BINARY) |
                     (config.threshold == ThresholdMode::kOtsu ? cv::THRESH_OTSU : 0);
    cv::threshold(grey, binary, config.fixed_threshold, 255, type);
    for (auto& contour : externalContours(binary)) {
      // Keep the contour for the colour it carries most.
      Candidate best;
      for (std::size_t c = 0; c < masks.size(); ++c) {
        Candidate candidate;
        if (describe(bgr, masks[c], contour, static_cast<int>(c), config, candidate) &&
            candidate.colour_fraction > best.colour_fraction) {
          best = std::move(candidate);
        }
      }
      if (best.colour_index >= 0) found.push_back(std::move(best));
    }
  }
  std::sort(found.begin(), found.end(), [](const Candidate& a, const Candidate& b) { return a.area_px > b.area_px; });
  if (found.size() > static_cast<std::size_t>(config.max_candidates)) found.resize(config.max_candidates);
  return found;
}

}  // namespace underwater_stereo
