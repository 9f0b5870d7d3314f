// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/candidate_finder.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/image_checks.h"

namespace underwater_stereo {

namespace {

/// Classes holding less than this share of a region are ignored when grouping it.
constexpr double kMinClassShare = 0.05;
/// Window over which the pixels of a region holding two colour groups are given to one of them.
constexpr int kGroupWindowPx = 11;

}  // namespace

// The mask is eroded: edges mix object and water.
double faceContrast(const cv::Mat& bgr_roi, const cv::Mat& mask) {
  cv::Mat grey, inner;
  cv::cvtColor(bgr_roi, grey, cv::COLOR_BGR2GRAY);
  cv::blur(grey, grey, cv::Size(5, 5));
  cv::erode(mask, inner, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(7, 7)));
  std::vector<std::uint8_t> values;
  for (int y = 0; y < inner.rows; ++y) {
    for (int x = 0; x < inner.cols; ++x) {
      if (inner.at<std::uint8_t>(y, x)) values.push_back(grey.at<std::uint8_t>(y, x));
    }
  }
  if (values.size() < 50) return 0.0;
  cv::Mat column(static_cast<int>(values.size()), 1, CV_8UC1, values.data()), split;
  const double t = cv::threshold(column, split, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
  double n[2] = {}, sum[2] = {}, sq[2] = {};
  for (const std::uint8_t v : values) {
    const int k = v > t;
    n[k] += 1;
    sum[k] += v;
    sq[k] += double(v) * v;
  }
  if (n[0] < 0.1 * values.size() || n[1] < 0.1 * values.size()) return 0.0;  // one level
  const double m0 = sum[0] / n[0], m1 = sum[1] / n[1];
  const double var = sq[0] / n[0] - m0 * m0 + sq[1] / n[1] - m1 * m1;
  return (m1 - m0) * (m1 - m0) / std::max(var, 1.0);
}

namespace {

/// Fills `candidate` from its contour and the colour mask it belongs to.
bool describe(const cv::Mat& bgr, const cv::Mat& colour_mask, std::vector<cv::Point> contour, int colour_index,
              const CandidateConfig& config, Candidate& out) {
  const double area = cv::contourArea(contour);
  if (area < config.min_area_px || area > config.max_area_px || contour.size() < 3) return false;
  out.roi = cv::boundingRect(contour);
  const cv::Mat filled = filledOutline(contour, out.roi);
  const int inside = cv::countNonZero(filled);
  out.mask = filled & colour_mask(out.roi);
  out.colour_fraction = inside > 0 ? cv::countNonZero(out.mask) / static_cast<double>(inside) : 0.0;
  if (out.colour_fraction < config.min_colour_fraction) return false;
  out.colour_index = colour_index;
  out.area_px = area;
  out.outline = classifyOutline(contour);
  out.mean_bgr = cv::mean(bgr(out.roi), out.mask);
  out.face_contrast = faceContrast(bgr(out.roi), out.mask);
  out.contour = std::move(contour);
  return true;
}

/// HSV value (max of B, G, R) of an object's pixels over that of a ring of water around its box.
double contrastToSurround(const cv::Mat& bgr, const Candidate& c) {
  const int margin = std::max(c.roi.width, c.roi.height) / 4 + 10;
  const cv::Rect outer = (c.roi + cv::Size(2 * margin, 2 * margin) - cv::Point(margin, margin)) &
                         cv::Rect(0, 0, bgr.cols, bgr.rows);
  cv::Mat value;
  cv::Mat channels[3];
  cv::split(bgr(outer), channels);
  value = cv::max(channels[0], cv::max(channels[1], channels[2]));
  cv::Mat ring(outer.size(), CV_8UC1, cv::Scalar(255));
  ring(c.roi - outer.tl()).setTo(0);
  const double surround = cv::countNonZero(ring) > 0 ? cv::mean(value, ring)[0] : 0.0;
  const double object = cv::mean(value(c.roi - outer.tl()), c.mask)[0];
  return surround > 0 ? object / surround : 0.0;
}

std::vector<std::vector<cv::Point>> externalContours(const cv::Mat& binary) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(binary, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  return contours;
}

/// One region of the union of all colour masks. Usually one object, whose shading may cross from one
/// colour class into its hue neighbour (a yellow ball's shadowed side reads orange): it becomes one candidate
/// labelled with its majority class. Classes present that are not hue neighbours of the majority (a red
/// buoy in front of a green one) become candidates of their own; each pixel of the region goes to the group
/// holding most raw pixels around it.
std::vector<Candidate> splitByHueGroup(const cv::Mat& bgr, const ColourMasks& masks,
                                       const std::vector<ColourClass>& classes, std::vector<cv::Point> contour,
                                       const CandidateConfig& config) {
  std::vector<Candidate> out;
  const double area = cv::contourArea(contour);
  if (area < config.min_area_px || area > config.max_area_px || contour.size() < 3) return out;
  const cv::Rect roi = cv::boundingRect(contour);
  const cv::Mat filled = filledOutline(contour, roi);
  const std::size_t n = classes.size();
  std::vector<int> counts(n);
  for (std::size_t c = 0; c < n; ++c) counts[c] = cv::countNonZero(masks.classes[c](roi) & filled);
  std::vector<std::size_t> order(n);
  for (std::size_t c = 0; c < n; ++c) order[c] = c;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return counts[a] > counts[b]; });
  const int total = std::max(1, cv::countNonZero(filled));
  std::vector<int> group(n, -1);
  std::vector<std::size_t> leaders;  // the majority class of each group
  for (std::size_t c : order) {
    if (counts[c] < kMinClassShare * total) break;
    for (std::size_t m = 0; m < n && group[c] < 0; ++m) {
      if (group[m] >= 0 && hueNeighbours(classes[m], classes[c])) group[c] = group[m];
    }
    if (group[c] < 0) {
      group[c] = static_cast<int>(leaders.size());
      leaders.push_back(c);
    }
  }
  if (leaders.empty()) return out;
  if (leaders.size() == 1) {
    Candidate candidate;
    if (describe(bgr, masks.any, std::move(contour), static_cast<int>(leaders[0]), config, candidate)) {
      out.push_back(std::move(candidate));
    }
    return out;
  }
  // Local density of each group's raw pixels; the densest group takes the pixel.
  std::vector<cv::Mat> density(leaders.size());
  for (std::size_t g = 0; g < leaders.size(); ++g) {
    cv::Mat raw = cv::Mat::zeros(roi.size(), CV_8UC1);
    for (std::size_t c = 0; c < n; ++c) {
      if (group[c] == static_cast<int>(g)) raw |= masks.classes[c](roi);
    }
    cv::boxFilter(raw, density[g], CV_32F, cv::Size(kGroupWindowPx, kGroupWindowPx));
  }
  const cv::Mat region = masks.any(roi) & filled;
  for (std::size_t g = 0; g < leaders.size(); ++g) {
    cv::Mat own = region.clone();
    for (std::size_t other = 0; other < leaders.size(); ++other) {
      if (other != g) own.setTo(0, density[other] > density[g]);
    }
    cv::Mat group_mask = cv::Mat::zeros(bgr.size(), CV_8UC1);
    own.copyTo(group_mask(roi));
    for (auto& part : externalContours(group_mask)) {
      Candidate candidate;
      if (describe(bgr, group_mask, std::move(part), static_cast<int>(leaders[g]), config, candidate)) {
        out.push_back(std::move(candidate));
      }
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> CandidateConfig::validate() const {
  std::vector<std::string> p;
  if (fixed_threshold < 0 || fixed_threshold > 255) p.push_back("candidates.fixed_threshold must be in [0, 255]");
  if (blur_kernel_px < 1 || blur_kernel_px % 2 == 0 || blur_kernel_px > 51) {
    p.push_back("candidates.blur_kernel_px must be odd, in [1, 51]");
  }
  // Each range as detectorTunables() gives it (detector_tunables_test checks that they agree), then their order.
  if (!(min_area_px >= 1 && min_area_px <= 1e6)) p.push_back("candidates.min_area_px must be in [1, 1000000]");
  if (!(max_area_px >= 2 && max_area_px <= 1e9)) p.push_back("candidates.max_area_px must be in [2, 1000000000]");
  if (!(min_area_px < max_area_px)) p.push_back("candidates: min_area_px must be under max_area_px");
  if (!(min_colour_fraction >= 0.01 && min_colour_fraction <= 1)) {
    p.push_back("candidates.min_colour_fraction must be in [0.01, 1]");
  }
  if (!(max_candidates >= 1 && max_candidates <= 1000)) p.push_back("candidates.max_candidates must be in [1, 1000]");
  return p;
}

cv::Mat filledOutline(const std::vector<cv::Point>& contour, const cv::Rect& box) {
  cv::Mat filled = cv::Mat::zeros(box.size(), CV_8UC1);
  cv::drawContours(filled, std::vector<std::vector<cv::Point>>{contour}, 0, 255, cv::FILLED, cv::LINE_8, cv::noArray(), 0,
                   -box.tl());
  return filled;
}

std::vector<cv::Point> largestOutline(const cv::Mat& mask, const cv::Point& origin) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, origin);  // (not modified since OpenCV 3.2)
  const auto largest = std::max_element(contours.begin(), contours.end(), [](const auto& a, const auto& b) {
    return cv::contourArea(a) < cv::contourArea(b);
  });
  if (largest == contours.end() || largest->size() < 3) return {};
  return std::move(*largest);
}

OutlineKind classifyOutline(const std::vector<cv::Point>& contour) {
  if (contour.size() < 3) throw std::invalid_argument("classifyOutline: a contour needs at least 3 points");
  const double perimeter = cv::arcLength(contour, true);
  const double area = cv::contourArea(contour);
  std::vector<cv::Point> poly;
  cv::approxPolyDP(contour, poly, 0.03 * perimeter, true);
  if (poly.size() == 3) return OutlineKind::kTriangle;
  if (poly.size() == 4 && cv::isContourConvex(poly)) {
    // Rectangle when the quadrilateral fills its minimum-area rectangle.
    const cv::RotatedRect box = cv::minAreaRect(contour);
    if (area > 0.85 * box.size.area()) return OutlineKind::kRectangle;
  }
  if (contour.size() >= 5 && area > 0) {
    const cv::RotatedRect e = cv::fitEllipse(contour);
    const double ellipse_area = M_PI * e.size.width * e.size.height / 4.0;
    if (std::abs(ellipse_area - area) < 0.06 * area) {
      const double ratio = std::min(e.size.width, e.size.height) / std::max(e.size.width, e.size.height);
      return ratio > 0.88 ? OutlineKind::kCircle : OutlineKind::kEllipse;
    }
  }
  return OutlineKind::kPolygon;
}

bool hueNeighbours(const ColourClass& a, const ColourClass& b) {
  // Circular gap between two hue ranges (each possibly wrapping through 0), in OpenCV hue units: one range admits
  // an end of the other, widened by the gap (both ways round: a range may lie inside the other).
  constexpr int kMaxGap = 2;
  const auto admitsAnEnd = [](const ColourClass& x, const ColourClass& y) {
    for (int d = 0; d <= kMaxGap; ++d) {
      if (x.admitsHue((y.hue_max + d) % 180) || x.admitsHue((y.hue_min - d + 180) % 180)) return true;
    }
    return false;
  };
  return admitsAnEnd(b, a) || admitsAnEnd(a, b);
}

std::vector<Candidate> findCandidates(const cv::Mat& bgr, const ColourMasks& masks,
                                      const std::vector<ColourClass>& classes, const CandidateConfig& config) {
  requireBgr8(bgr, "findCandidates");
  if (masks.classes.size() != classes.size()) {
    throw std::invalid_argument("findCandidates: " + std::to_string(masks.classes.size()) + " masks for " +
                                std::to_string(classes.size()) + " colour classes");
  }
  std::vector<cv::Mat> all = masks.classes;
  all.push_back(masks.any);
  for (const cv::Mat& m : all) {
    if (m.size() != bgr.size() || m.type() != CV_8UC1) {
      throw std::invalid_argument("findCandidates: each colour mask must be CV_8UC1 of the image's size");
    }
  }
  if (config.source == ContourSource::kLearned) {
    throw std::invalid_argument("findCandidates: candidates.source learned is searched by findLearnedCandidates");
  }
  std::vector<Candidate> found;
  if (config.source == ContourSource::kColourMask) {
    for (auto& contour : externalContours(masks.any)) {
      for (Candidate& c : splitByHueGroup(bgr, masks, classes, std::move(contour), config)) {
        found.push_back(std::move(c));
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
      for (std::size_t c = 0; c < classes.size(); ++c) {
        Candidate candidate;
        if (describe(bgr, masks.classes[c], contour, static_cast<int>(c), config, candidate) &&
            candidate.colour_fraction > best.colour_fraction) {
          best = std::move(candidate);
        }
      }
      if (best.colour_index >= 0) found.push_back(std::move(best));
    }
  }
  found.erase(std::remove_if(found.begin(), found.end(),
                             [&](const Candidate& c) {
                               const double needed = classes[c.colour_index].min_contrast;
                               return needed > 0 && contrastToSurround(bgr, c) < needed;
                             }),
              found.end());
  std::sort(found.begin(), found.end(), [](const Candidate& a, const Candidate& b) { return a.area_px > b.area_px; });
  if (found.size() > static_cast<std::size_t>(config.max_candidates)) found.resize(config.max_candidates);
  return found;
}

}  // namespace underwater_stereo
