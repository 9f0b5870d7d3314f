// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/sim/voc_labels.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace underwater_stereo {
namespace sim {
namespace {

std::string escaped(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

std::vector<std::size_t> labelledObjects(const std::vector<GroundTruthObject>& truth,
                                         const std::vector<std::string>& labelled_colours) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const bool labelled =
        std::find(labelled_colours.begin(), labelled_colours.end(), truth[i].colour) != labelled_colours.end();
    const cv::Rect& box = truth[i].roi_left;
    if (labelled && truth[i].visible_pixels > 0 && box.width > 1 && box.height > 1) out.push_back(i);
  }
  return out;
}

std::string vocAnnotation(const std::string& filename, const cv::Size& size, const std::vector<GroundTruthObject>& truth,
                          const std::vector<std::size_t>& labelled, int min_pixels) {
  std::ostringstream x;
  x << "<annotation>\n"
    << "  <folder>images</folder>\n"
    << "  <filename>" << escaped(filename) << "</filename>\n"
    << "  <source><database>underwater_stereo simulator</database></source>\n"
    << "  <size><width>" << size.width << "</width><height>" << size.height << "</height><depth>3</depth></size>\n"
    << "  <segmented>1</segmented>\n";
  for (const std::size_t i : labelled) {
    if (i >= truth.size()) throw std::invalid_argument("vocAnnotation: object index " + std::to_string(i) + " out of range");
    const GroundTruthObject& g = truth[i];
    const cv::Rect& r = g.roi_left;
    if (g.visible_pixels <= 0 || r.empty()) {
      throw std::invalid_argument("vocAnnotation: object '" + g.name + "' shows no pixel");
    }
    const bool truncated = r.x == 0 || r.y == 0 || r.br().x == size.width || r.br().y == size.height;
    x << "  <object>\n"
      << "    <name>" << escaped(g.colour) << "</name>\n"
      << "    <pose>Unspecified</pose>\n"
      << "    <truncated>" << truncated << "</truncated>\n"
      << "    <difficult>" << (g.visible_pixels < min_pixels) << "</difficult>\n"
      << "    <bndbox><xmin>" << r.x + 1 << "</xmin><ymin>" << r.y + 1 << "</ymin><xmax>" << r.x + r.width
      << "</xmax><ymax>" << r.y + r.height << "</ymax></bndbox>\n"
      << "  </object>\n";
  }
  x << "</annotation>\n";
  return x.str();
}

cv::Mat labelMask(const cv::Mat& left_labels, const std::vector<std::size_t>& labelled) {
  if (left_labels.type() != CV_16UC1) throw std::invalid_argument("labelMask: left_labels must be CV_16UC1");
  if (labelled.size() > 255) throw std::invalid_argument("labelMask: more than 255 labelled objects");
  std::vector<std::uint8_t> lut(65536, 0);
  for (std::size_t k = 0; k < labelled.size(); ++k) {
    if (labelled[k] + 1 < lut.size()) lut[labelled[k] + 1] = static_cast<std::uint8_t>(k + 1);
  }
  cv::Mat mask(left_labels.size(), CV_8UC1);
  for (int v = 0; v < mask.rows; ++v) {
    const auto* in = left_labels.ptr<std::uint16_t>(v);
    auto* out = mask.ptr<std::uint8_t>(v);
    for (int u = 0; u < mask.cols; ++u) out[u] = lut[in[u]];
  }
  return mask;
}

}  // namespace sim
}  // namespace underwater_stereo
