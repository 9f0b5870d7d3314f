// SPDX-License-Identifier: BSD-3-Clause
// A frame converted only where needed gives the same pixels as converting it all.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "underwater_stereo/detection/raw_frame.h"

using namespace underwater_stereo;

namespace {

/// A smooth colour image and its RGGB mosaic (R at even rows/columns, B at odd/odd).
struct Mosaic {
  cv::Mat bgr, rggb;
};

Mosaic mosaicOfGradient(cv::Size size) {
  Mosaic m;
  m.bgr.create(size, CV_8UC3);
  m.rggb.create(size, CV_8UC1);
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      const cv::Vec3b c(static_cast<std::uint8_t>(40 + x % 150), static_cast<std::uint8_t>(60 + (x + y) % 120),
                        static_cast<std::uint8_t>(30 + y % 200));
      m.bgr.at<cv::Vec3b>(y, x) = c;
      const int channel = (y % 2 == 0 && x % 2 == 0) ? 2 : (y % 2 == 1 && x % 2 == 1) ? 0 : 1;
      m.rggb.at<std::uint8_t>(y, x) = c[channel];
    }
  }
  return m;
}

}  // namespace

TEST(RawFrame, RegionsDemosaicAsTheWholeFrame) {
  const Mosaic m = mosaicOfGradient({64, 48});
  cv::Mat whole_bgr, whole_grey;
  cv::cvtColor(m.rggb, whole_bgr, cv::COLOR_BayerBG2BGR);  // what cv_bridge does with bayer_rggb8
  cv::cvtColor(m.rggb, whole_grey, cv::COLOR_BayerBG2GRAY);
  const RawFrame frame(m.rggb, pixelLayoutOf("bayer_rggb8"));
  EXPECT_EQ(cv::norm(frame.bgr(), whole_bgr, cv::NORM_INF), 0);
  // Regions at every parity of x and y, away from the frame's edge.
  for (const cv::Rect region : {cv::Rect(10, 8, 20, 14), cv::Rect(11, 8, 20, 14), cv::Rect(10, 9, 21, 15), cv::Rect(13, 7, 17, 19)}) {
    EXPECT_EQ(cv::norm(frame.bgr(region), whole_bgr(region), cv::NORM_INF), 0) << region;
    // OpenCV's vectorised and scalar Bayer-to-grey loops round differently: within one level.
    EXPECT_LE(cv::norm(frame.grey(region), whole_grey(region), cv::NORM_INF), 1) << region;
  }
}

TEST(RawFrame, HalfSizeTakesEachCellsColours) {
  const Mosaic m = mosaicOfGradient({64, 48});
  for (const std::string encoding : {"bayer_rggb8", "bayer_grbg8", "bayer_gbrg8", "bayer_bggr8"}) {
    // The same scene mosaicked in each layout = the RGGB mosaic seen from an offset of 0 or 1 in x and y.
    const int dx = encoding == "bayer_grbg8" || encoding == "bayer_bggr8" ? 1 : 0;
    const int dy = encoding == "bayer_gbrg8" || encoding == "bayer_bggr8" ? 1 : 0;
    const cv::Rect view(dx, dy, 60, 44);
    const cv::Mat half = RawFrame(m.rggb(view).clone(), pixelLayoutOf(encoding)).halfSizeBgr();
    ASSERT_EQ(half.size(), cv::Size(30, 22));
    for (int i = 0; i < half.cols * half.rows; ++i) {  // every cell: the vectorised loop's and its tail's
      const cv::Point p(i % half.cols, i / half.cols);
      const int x = view.x + 2 * p.x, y = view.y + 2 * p.y;  // the cell's top-left in the RGGB mosaic
      const cv::Vec3b got = half.at<cv::Vec3b>(p);
      auto px = [&](int u, int v) { return static_cast<int>(m.rggb.at<std::uint8_t>(v, u)); };
      // In the RGGB mosaic R is at even/even, B at odd/odd.
      const int r = px(x + (x % 2), y + (y % 2)), b = px(x + 1 - (x % 2), y + 1 - (y % 2));
      const int g = (px(x + 1 - (x % 2), y + (y % 2)) + px(x + (x % 2), y + 1 - (y % 2)) + 1) / 2;
      ASSERT_EQ(got, cv::Vec3b(b, g, r)) << encoding << " at " << p;
    }
  }
  // A region's half size is the whole half-size frame's part; BGR frames are area-averaged.
  const RawFrame frame(m.rggb, PixelLayout::kBayerRggb);
  EXPECT_EQ(cv::norm(frame.halfSizeBgr(cv::Rect(10, 6, 20, 16)), frame.halfSizeBgr()(cv::Rect(5, 3, 10, 8)), cv::NORM_INF), 0);
  cv::Mat area;
  cv::resize(m.bgr, area, cv::Size(32, 24), 0, 0, cv::INTER_AREA);
  EXPECT_EQ(cv::norm(RawFrame(m.bgr).halfSizeBgr(), area, cv::NORM_INF), 0);
}

TEST(RawFrame, GreyAndBgrFramesPassThrough) {
  const Mosaic m = mosaicOfGradient({32, 24});
  const RawFrame bgr(m.bgr);
  EXPECT_EQ(bgr.layout(), PixelLayout::kBgr);
  EXPECT_EQ(bgr.bgr(cv::Rect(3, 4, 5, 6)).data, m.bgr(cv::Rect(3, 4, 5, 6)).data);  // shared, not copied
  cv::Mat grey;
  cv::cvtColor(m.bgr, grey, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(cv::norm(bgr.grey(cv::Rect(0, 0, 32, 24)), grey, cv::NORM_INF), 0);
  const RawFrame mono(grey);
  EXPECT_EQ(mono.layout(), PixelLayout::kMono);
  EXPECT_EQ(mono.bgr().channels(), 3);
  EXPECT_FALSE(carriesColour(mono.layout()));
  EXPECT_TRUE(carriesColour(bgr.layout()));
  EXPECT_TRUE(carriesColour(PixelLayout::kBayerGbrg));
}

TEST(RawFrame, BadInputIsRefused) {
  EXPECT_THROW(RawFrame(cv::Mat()), std::invalid_argument);
  EXPECT_THROW(RawFrame(cv::Mat(4, 4, CV_16UC1)), std::invalid_argument);
  EXPECT_THROW(RawFrame(cv::Mat(4, 4, CV_8UC3), PixelLayout::kBayerRggb), std::invalid_argument);
  EXPECT_THROW(RawFrame(cv::Mat(5, 4, CV_8UC1), PixelLayout::kBayerRggb), std::invalid_argument);
  EXPECT_THROW(pixelLayoutOf("rgb16"), std::invalid_argument);
  const RawFrame frame(cv::Mat(8, 8, CV_8UC1, cv::Scalar(7)), PixelLayout::kBayerGbrg);
  EXPECT_THROW(frame.bgr(cv::Rect(4, 4, 8, 8)), std::invalid_argument);
  EXPECT_THROW(frame.halfSizeBgr(cv::Rect(1, 0, 4, 4)), std::invalid_argument);
}
