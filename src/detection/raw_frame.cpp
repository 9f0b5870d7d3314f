// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/raw_frame.h"

#include <opencv2/core/utility.hpp>
#include <opencv2/core/hal/intrin.hpp>
#include <opencv2/imgproc.hpp>

#include <optional>
#include <stdexcept>
#include <utility>

namespace underwater_stereo {
namespace {

bool isBayer(PixelLayout layout) { return layout != PixelLayout::kBgr && layout != PixelLayout::kMono; }

/// The layout of the mosaic seen from (x, y): an odd offset swaps the cell's columns, rows or both.
PixelLayout shifted(PixelLayout layout, int x, int y) {
  const bool swap_columns = (x & 1) != 0, swap_rows = (y & 1) != 0;
  auto swapColumns = [](PixelLayout l) {
    switch (l) {
      case PixelLayout::kBayerRggb: return PixelLayout::kBayerGrbg;
      case PixelLayout::kBayerGrbg: return PixelLayout::kBayerRggb;
      case PixelLayout::kBayerBggr: return PixelLayout::kBayerGbrg;
      case PixelLayout::kBayerGbrg: return PixelLayout::kBayerBggr;
      default: return l;
    }
  };
  auto swapRows = [](PixelLayout l) {
    switch (l) {
      case PixelLayout::kBayerRggb: return PixelLayout::kBayerGbrg;
      case PixelLayout::kBayerGbrg: return PixelLayout::kBayerRggb;
      case PixelLayout::kBayerBggr: return PixelLayout::kBayerGrbg;
      case PixelLayout::kBayerGrbg: return PixelLayout::kBayerBggr;
      default: return l;
    }
  };
  if (swap_columns) layout = swapColumns(layout);
  if (swap_rows) layout = swapRows(layout);
  return layout;
}

/// OpenCV's demosaicing code for a layout (OpenCV names a mosaic by its second row's middle pair, so
/// bayer_rggb8 is BayerBG, as in cv_bridge).
int demosaicCode(PixelLayout layout, bool to_grey) {
  switch (layout) {
    case PixelLayout::kBayerRggb: return to_grey ? cv::COLOR_BayerBG2GRAY : cv::COLOR_BayerBG2BGR;
    case PixelLayout::kBayerBggr: return to_grey ? cv::COLOR_BayerRG2GRAY : cv::COLOR_BayerRG2BGR;
    case PixelLayout::kBayerGbrg: return to_grey ? cv::COLOR_BayerGR2GRAY : cv::COLOR_BayerGR2BGR;
    case PixelLayout::kBayerGrbg: return to_grey ? cv::COLOR_BayerGB2GRAY : cv::COLOR_BayerGB2BGR;
    default: throw std::logic_error("demosaicCode: not a Bayer layout");
  }
}

void requireInside(const cv::Rect& region, const cv::Size& size, const char* who) {
  if (region.empty() || (region & cv::Rect(cv::Point(), size)) != region) {
    throw std::invalid_argument(std::string(who) + ": region outside the frame");
  }
}

/// Demosaiced `region` of a Bayer frame: a region two pixels larger is demosaiced (OpenCV treats its input's
/// edge specially) and cropped.
cv::Mat demosaic(const cv::Mat& mosaic, PixelLayout layout, const cv::Rect& region, bool to_grey) {
  const cv::Rect grown = cv::Rect(region.x - 2, region.y - 2, region.width + 4, region.height + 4) &
                         cv::Rect(cv::Point(), mosaic.size());
  cv::Mat out;
  cv::cvtColor(mosaic(grown), out, demosaicCode(shifted(layout, grown.x, grown.y), to_grey));
  return out(region - grown.tl()).clone();
}

}  // namespace

std::optional<PixelLayout> layoutOfEncoding(const std::string& encoding) {
  static const std::pair<const char*, PixelLayout> kLayouts[] = {
      {"bgr8", PixelLayout::kBgr},               {"mono8", PixelLayout::kMono},
      {"bayer_rggb8", PixelLayout::kBayerRggb}, {"bayer_bggr8", PixelLayout::kBayerBggr},
      {"bayer_gbrg8", PixelLayout::kBayerGbrg}, {"bayer_grbg8", PixelLayout::kBayerGrbg}};
  for (const auto& [name, layout] : kLayouts) {
    if (encoding == name) return layout;
  }
  return std::nullopt;
}

bool carriesColour(PixelLayout layout) { return layout != PixelLayout::kMono; }

PixelLayout pixelLayoutOf(const std::string& encoding) {
  if (const auto layout = layoutOfEncoding(encoding)) return *layout;
  throw std::invalid_argument("pixelLayoutOf: encoding '" + encoding +
                              "' is not bgr8, mono8 or bayer_rggb8/bggr8/gbrg8/grbg8");
}

RawFrame::RawFrame(const cv::Mat& image)
    : RawFrame(image, image.type() == CV_8UC1 ? PixelLayout::kMono : PixelLayout::kBgr) {}

RawFrame::RawFrame(const cv::Mat& data, PixelLayout layout) : data_(data), layout_(layout) {
  if (data.empty()) throw std::invalid_argument("RawFrame: empty image");
  if (data.type() != (layout == PixelLayout::kBgr ? CV_8UC3 : CV_8UC1)) {
    throw std::invalid_argument(std::string("RawFrame: ") +
                                (layout == PixelLayout::kBgr ? "BGR needs 8-bit 3-channel" : "grey and Bayer need 8-bit 1-channel") +
                                " data, got " + std::to_string(data.channels()) + " channel(s) of depth " +
                                std::to_string(data.depth()));
  }
  if (isBayer(layout) && (data.cols % 2 != 0 || data.rows % 2 != 0)) {
    throw std::invalid_argument("RawFrame: a Bayer frame needs even width and height, got " + std::to_string(data.cols) +
                                "x" + std::to_string(data.rows));
  }
}

cv::Mat RawFrame::bgr(const cv::Rect& region) const {
  requireInside(region, size(), "RawFrame::bgr");
  if (layout_ == PixelLayout::kBgr) return data_(region);
  cv::Mat out;
  if (layout_ == PixelLayout::kMono) {
    cv::cvtColor(data_(region), out, cv::COLOR_GRAY2BGR);
    return out;
  }
  return demosaic(data_, layout_, region, false);
}

cv::Mat RawFrame::grey(const cv::Rect& region) const {
  requireInside(region, size(), "RawFrame::grey");
  if (layout_ == PixelLayout::kMono) return data_(region);
  if (layout_ == PixelLayout::kBgr) {
    cv::Mat out;
    cv::cvtColor(data_(region), out, cv::COLOR_BGR2GRAY);
    return out;
  }
  return demosaic(data_, layout_, region, true);
}

cv::Mat RawFrame::halfSizeBgr(const cv::Rect& region) const {
  requireInside(region, size(), "RawFrame::halfSizeBgr");
  if (region.x % 2 != 0 || region.y % 2 != 0) throw std::invalid_argument("RawFrame::halfSizeBgr: region not on even pixels");
  const cv::Size half(region.width / 2, region.height / 2);
  cv::Mat out;
  if (!isBayer(layout_)) {
    cv::resize(bgr(region), out, half, 0, 0, cv::INTER_AREA);
    return out;
  }
  // Where R and B sit in the region's first cell, numbered 0 1 / 2 3 (the G's are the other two).
  const PixelLayout l = shifted(layout_, region.x, region.y);
  const int r = l == PixelLayout::kBayerRggb ? 0 : l == PixelLayout::kBayerGrbg ? 1 : l == PixelLayout::kBayerGbrg ? 2 : 3;
  const int b = 3 - r, g1 = r == 0 || r == 3 ? 1 : 0, g2 = 3 - g1;
  out.create(half, CV_8UC3);
  const cv::Mat src = data_(region);
  cv::parallel_for_(cv::Range(0, half.height), [&](const cv::Range& rows) {
    for (int v = rows.start; v < rows.end; ++v) {
      const std::uint8_t* cell[2] = {src.ptr<std::uint8_t>(2 * v), src.ptr<std::uint8_t>(2 * v + 1)};
      const std::uint8_t *red = cell[r / 2] + r % 2, *blue = cell[b / 2] + b % 2;
      const std::uint8_t *green1 = cell[g1 / 2] + g1 % 2, *green2 = cell[g2 / 2] + g2 % 2;
      auto* o = out.ptr<std::uint8_t>(v);
      int u = 0;
#if CV_SIMD
      // A cell row's 2 x lanes raw pixels per row at a time: even and odd columns apart, the cell's four
      // values picked as in the scalar loop below, green their rounded mean ((a + b + 1) >> 1).
      const int lanes = cv::v_uint8::nlanes;
      for (; u <= half.width - lanes; u += lanes, o += 3 * lanes) {
        cv::v_uint8 c[4];
        cv::v_load_deinterleave(cell[0] + 2 * u, c[0], c[1]);
        cv::v_load_deinterleave(cell[1] + 2 * u, c[2], c[3]);
        cv::v_uint16 g1_16[2], g2_16[2];
        cv::v_expand(c[g1], g1_16[0], g1_16[1]);
        cv::v_expand(c[g2], g2_16[0], g2_16[1]);
        cv::v_store_interleave(o, c[b], cv::v_rshr_pack<1>(g1_16[0] + g2_16[0], g1_16[1] + g2_16[1]), c[r]);
      }
#endif
      for (; u < half.width; ++u, o += 3) {
        o[0] = blue[2 * u];
        o[1] = static_cast<std::uint8_t>((green1[2 * u] + green2[2 * u] + 1) >> 1);
        o[2] = red[2 * u];
      }
    }
  });
  return out;
}

}  // namespace underwater_stereo
