// SPDX-License-Identifier: BSD-3-Clause
// The water model: a pixel's contrast with the local water is log((I + o) / (B + o)); objects seen through
// water of any colour, at any transmission, stand out and are proposed.
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <utility>
#include <vector>

#include "underwater_stereo/detection/area_shrink.h"
#include "underwater_stereo/detection/blob_proposals.h"
#include "underwater_stereo/detection/water_contrast.h"

using namespace underwater_stereo;

namespace {

struct Water {
  const char* name;
  cv::Vec3d veil;  ///< B, G, R of the water far away, 0-255
};
const Water kWaters[] = {{"clear blue", {190, 120, 40}}, {"green", {90, 150, 70}}, {"brown", {50, 110, 120}}};

/// What the camera sees of an object of own colour `j` with transmission t: I = J t + B (1 - t).
cv::Vec3b seen(const cv::Vec3d& j, const cv::Vec3d& b, double t) {
  cv::Vec3b out;
  for (int c = 0; c < 3; ++c) out[c] = cv::saturate_cast<uchar>(j[c] * t + b[c] * (1 - t));
  return out;
}

/// A 640x480 frame of water (a gentle vertical gradient plus sensor noise) with one disc of colour `object`.
cv::Mat frameWith(const cv::Vec3d& water, const cv::Vec3b& object, cv::Point centre, int radius, unsigned seed) {
  cv::Mat frame(480, 640, CV_8UC3);
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 2.0);
  for (int y = 0; y < frame.rows; ++y) {
    const double k = 1.15 - 0.3 * y / frame.rows;  // brighter towards the surface
    for (int x = 0; x < frame.cols; ++x) {
      for (int c = 0; c < 3; ++c) frame.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(water[c] * k + noise(rng));
    }
  }
  cv::Mat disc = cv::Mat::zeros(frame.size(), CV_8UC1);
  cv::circle(disc, centre, radius, 255, cv::FILLED);
  for (int y = 0; y < frame.rows; ++y) {
    for (int x = 0; x < frame.cols; ++x) {
      if (!disc.at<uchar>(y, x)) continue;
      const double k = 1.15 - 0.3 * y / frame.rows;
      for (int c = 0; c < 3; ++c) frame.at<cv::Vec3b>(y, x)[c] = cv::saturate_cast<uchar>(object[c] * k + noise(rng));
    }
  }
  return frame;
}

}  // namespace

TEST(WaterContrast, MeasuresTheLogRatioToTheLocalWater) {
  for (const Water& w : kWaters) {
    const cv::Vec3d red_buoy(20, 30, 220);
    for (double t : {0.9, 0.5, 0.2}) {
      const cv::Vec3b object = seen(red_buoy, w.veil, t);
      const cv::Mat frame = frameWith(w.veil, object, {320, 240}, 30, 7);
      const WaterContrast wc = measureWaterContrast(frame, WaterContrastConfig{});
      // The local water under the object is the water around it (the object is small against the window).
      const cv::Vec3b water = wc.water.at<cv::Vec3b>(240, 320);
      const double k = 1.15 - 0.3 * 240 / 480.0;
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(water[c], w.veil[c] * k, 4.0) << w.name << " t=" << t << " channel " << c;
        const double expected = std::log((object[c] * k + 4) / (w.veil[c] * k + 4));
        const double measured = cv::mean(wc.contrast(cv::Rect(310, 230, 20, 20)))[c];
        EXPECT_NEAR(measured, expected, 0.05) << w.name << " t=" << t << " channel " << c;
      }
      // A red object moves the colour towards red whatever the water: red gains most against it.
      const cv::Scalar mean = cv::mean(wc.contrast(cv::Rect(310, 230, 20, 20)));
      const cv::Vec3f chroma = chromaOf(cv::Vec3f(mean[0], mean[1], mean[2]));
      EXPECT_GT(chroma[2], chroma[0]) << w.name << " t=" << t;
      EXPECT_GT(chroma[2], chroma[1]) << w.name << " t=" << t;
    }
  }
}

TEST(WaterContrast, AnObjectWiderThanTheWindowIsNotItsOwnWater) {
  // A buoy 300 px across against a window of 5 / 32 of 640 = 100 px: the median over the window in its middle
  // is the buoy itself. Left out of the water, its middle is measured against the water around it.
  for (const Water& w : kWaters) {
    const cv::Vec3b object = seen({20, 30, 220}, w.veil, 0.6);
    const cv::Mat frame = frameWith(w.veil, object, {320, 240}, 150, 11);
    const double k = 1.15 - 0.3 * 240 / 480.0;
    WaterContrastConfig without;
    without.object_level = 0;
    const cv::Vec3b own = measureWaterContrast(frame, without).water.at<cv::Vec3b>(240, 320);
    const WaterContrast wc = measureWaterContrast(frame, WaterContrastConfig{});
    const cv::Vec3b water = wc.water.at<cv::Vec3b>(240, 320);
    double own_off = 0;
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(water[c], w.veil[c] * k, 8.0) << w.name << " channel " << c;
      own_off = std::max(own_off, std::abs(own[c] - w.veil[c] * k));
      const double expected = std::log((object[c] * k + 4) / (w.veil[c] * k + 4));
      const double measured = cv::mean(wc.contrast(cv::Rect(310, 230, 20, 20)))[c];
      EXPECT_NEAR(measured, expected, 0.08) << w.name << " channel " << c;
    }
    EXPECT_GT(own_off, 30) << w.name << ": without leaving it out, the buoy is its own water";
    // The whole buoy stands out, its middle as much as its rim.
    EXPECT_GT(cv::mean(wc.saliency[0](cv::Rect(310, 230, 20, 20)))[0], 8) << w.name;
  }
}

TEST(WaterContrast, RegionsWhoseHullsCoverMostOfTheFrameAreNotLeftOut) {
  // A thin ring of buoy colour whose hull is more than half the frame: the water is not taken from far away
  // (it may be the objects that are the exception, or the water): the window's median stays.
  const cv::Vec3d water(90, 150, 70);
  cv::Mat frame = frameWith(water, seen({20, 30, 220}, water, 0.6), {320, 240}, 0, 13);
  cv::circle(frame, {320, 240}, 230, cv::Scalar(seen({20, 30, 220}, water, 0.6)), 8);
  WaterContrastConfig without;
  without.object_level = 0;
  EXPECT_EQ(cv::norm(measureWaterContrast(frame, {}).water, measureWaterContrast(frame, without).water, cv::NORM_INF), 0.0);
}

TEST(WaterContrast, SaliencyIsNormalisedByTheFrame) {
  // The same object against the same water stands out alike in a dim and a bright exposure.
  const cv::Vec3d water(90, 150, 70);
  const cv::Vec3b object = seen({20, 30, 220}, water, 0.4);
  const cv::Mat bright = frameWith(water, object, {320, 240}, 30, 3);
  cv::Mat dim;
  bright.convertTo(dim, CV_8UC3, 0.5);
  const double s_bright = cv::mean(measureWaterContrast(bright, {}).saliency[0](cv::Rect(310, 230, 20, 20)))[0];
  const double s_dim = cv::mean(measureWaterContrast(dim, {}).saliency[0](cv::Rect(310, 230, 20, 20)))[0];
  EXPECT_GT(s_bright, 8);
  EXPECT_GT(s_dim, 8);
}

TEST(WaterContrast, AgainstGivenWaterEqualsOwnMeasurement) {
  const cv::Vec3d water(90, 150, 70);
  const cv::Mat frame = frameWith(water, seen({20, 30, 220}, water, 0.5), {320, 240}, 30, 5);
  const WaterContrast whole = measureWaterContrast(frame, {});
  const cv::Rect part(200, 120, 240, 240);
  const WaterContrast cut = contrastAgainst(frame(part), whole.water(part), whole.stats, {});
  EXPECT_EQ(cv::norm(cut.saliency[1], whole.saliency[1](part), cv::NORM_INF), 0.0);
}

TEST(WaterContrast, RejectsBadInput) {
  EXPECT_THROW(measureWaterContrast(cv::Mat(), {}), std::invalid_argument);
  EXPECT_THROW(measureWaterContrast(cv::Mat(10, 10, CV_8UC1), {}), std::invalid_argument);
  WaterContrastConfig bad;
  bad.background_scale = 0;
  bad.ratio_offset = -1;
  bad.object_level = -1;
  EXPECT_EQ(bad.validate().size(), 3u);
  EXPECT_THROW(measureWaterContrast(cv::Mat(10, 10, CV_8UC3), bad), std::invalid_argument);
  const cv::Mat img(20, 20, CV_8UC3, cv::Scalar(1, 2, 3));
  EXPECT_THROW(contrastAgainst(img, cv::Mat(10, 10, CV_8UC3), ContrastStats{}, {}), std::invalid_argument);
}

TEST(BlobProposals, ProposeAFadedObjectInAnyWater) {
  // A dark red buoy far away (transmission 0.15: little of its red left) is still proposed, where it is.
  for (const Water& w : kWaters) {
    const cv::Mat frame = frameWith(w.veil, seen({20, 30, 200}, w.veil, 0.15), {400, 300}, 18, 11);
    const std::vector<BlobProposal> found = proposeBlobs(frame, measureWaterContrast(frame, {}), ProposalConfig{});
    bool hit = false;
    for (const BlobProposal& b : found) {
      ASSERT_EQ(b.features.size(), static_cast<std::size_t>(kBlobFeatureCount));
      const double area = M_PI * 18 * 18;
      if ((b.roi & cv::Rect(382, 282, 37, 37)).area() > 0.7 * b.roi.area() && std::abs(b.area_px - area) < 0.35 * area) hit = true;
    }
    EXPECT_TRUE(hit) << w.name << ": " << found.size() << " proposals, none on the buoy";
    EXPECT_LT(found.size(), 20u) << w.name << ": plain water proposed";
  }
}

TEST(BlobProposals, FeatureNamesMatchTheCount) {
  EXPECT_EQ(blobFeatureNames().size(), static_cast<std::size_t>(kBlobFeatureCount));
  ProposalConfig bad;
  bad.levels.clear();
  bad.min_area_px = 0;
  EXPECT_EQ(bad.validate().size(), 2u);
}

// A cut only in salientBand's rows finds what a cut of the whole frame finds: the whole mask is empty outside
// the band and equal inside it, at every kind and level, with objects near the frame's top and bottom edges;
// the proposals are the same with and without the rows' maxima.
TEST(BlobProposals, CuttingOnlyTheSalientBandChangesNothing) {
  for (const cv::Point centre : {cv::Point(400, 300), cv::Point(100, 4), cv::Point(500, 476)}) {
    cv::Mat frame = frameWith(kWaters[1].veil, seen({20, 30, 200}, kWaters[1].veil, 0.4), centre, 20, 5);
    cv::circle(frame, {200, 120}, 9, cv::Scalar(30, 200, 230), cv::FILLED);
    const WaterContrast contrast = measureWaterContrast(frame, {});
    ASSERT_EQ(contrast.row_max[0].size(), static_cast<std::size_t>(frame.rows));
    const ProposalConfig config;
    int empty = 0, narrow = 0;
    for (const SaliencyKind kind : {SaliencyKind::kChroma, SaliencyKind::kFull}) {
      for (const double level : config.levels) {
        const cv::Mat whole = salientMask(contrast, kind, level);
        const cv::Rect band = salientBand(contrast, kind, level);
        cv::Mat outside = whole.clone();
        if (band.empty()) {
          ++empty;
        } else {
          EXPECT_EQ(cv::countNonZero(salientMask(contrast, kind, level, band) != whole(band)), 0) << level;
          outside(band).setTo(0);
          narrow += band.height < frame.rows;
        }
        EXPECT_EQ(cv::countNonZero(outside), 0) << "mask outside the band at level " << level;
      }
    }
    EXPECT_GT(narrow, 0) << "some cut skips rows";
    WaterContrast without = contrast;
    without.row_max[0].clear();
    without.row_max[1].clear();
    const auto a = proposeBlobs(frame, contrast, config), b = proposeBlobs(frame, without, config);
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].roi, b[i].roi);
      EXPECT_EQ(a[i].contour, b[i].contour);
      EXPECT_EQ(a[i].features, b[i].features);
    }
    std::cout << "object at " << centre << ": " << a.size() << " proposals, " << empty << " empty cuts, " << narrow
              << " cuts on fewer rows" << std::endl;
    EXPECT_THROW(salientMask(contrast, SaliencyKind::kFull, 4, cv::Rect(0, 470, 640, 20)), std::invalid_argument);
    EXPECT_THROW(salientMask(contrast, SaliencyKind::kFull, 4, cv::Rect()), std::invalid_argument);
  }
}

namespace {

/// Whether boxes `a` and `b` are nearly the same (their intersection over 80 % of their union).
bool nearlyBox(const cv::Rect& a, const cv::Rect& b) { return (a & b).area() > 0.8 * (a | b).area(); }

/// The regions proposed in `frame` and the pieces cutIntoPieces cuts them into.
struct ProposedAndCut {
  std::vector<BlobProposal> regions, pieces;
};

ProposedAndCut proposeAndCut(const cv::Mat& frame, const ProposalConfig& config) {
  const WaterContrast contrast = measureWaterContrast(frame, {});
  ProposedAndCut out;
  out.regions = proposeBlobs(frame, contrast, config);
  std::vector<const BlobProposal*> regions;
  for (const BlobProposal& b : out.regions) regions.push_back(&b);
  out.pieces = cutIntoPieces(frame, contrast, regions, config);
  return out;
}

/// The first of `proposals` with nearly the box `box` (nearlyBox), or nullptr.
const BlobProposal* firstNearly(const std::vector<BlobProposal>& proposals, const cv::Rect& box) {
  const auto it =
      std::find_if(proposals.begin(), proposals.end(), [&](const BlobProposal& b) { return nearlyBox(b.roi, box); });
  return it == proposals.end() ? nullptr : &*it;
}

/// Whether one of `proposals` has nearly the box `box`.
bool anyNearly(const std::vector<BlobProposal>& proposals, const cv::Rect& box) {
  return firstNearly(proposals, box) != nullptr;
}

}  // namespace

// A green panel in front of a red buoy is one region at every level, which its steps cut into pieces, one on each
// object; a lone buoy, and the pair with piece_step 0, give no piece.
TEST(BlobProposals, TouchingObjectsOfTwoColoursAreCutIntoPieces) {
  const cv::Vec3d water = kWaters[0].veil;
  const cv::Rect buoy(270, 170, 50, 61), panel(320, 150, 90, 100);  // the buoy's visible part
  const cv::Mat lone = frameWith(water, seen({20, 30, 200}, water, 0.6), {300, 200}, 30, 3);
  cv::Mat pair = lone.clone();
  pair(panel).setTo(cv::Scalar(seen({40, 160, 30}, water, 0.6)));
  ProposalConfig config;
  config.min_area_px = 25;
  const double shipped = config.piece_step;
  for (const auto& [frame, step] : {std::pair{lone, shipped}, std::pair{pair, shipped}, std::pair{pair, 0.0}}) {
    config.piece_step = step;
    const ProposedAndCut cut = proposeAndCut(frame, config);
    for (const BlobProposal& b : cut.regions) EXPECT_FALSE(b.piece);
    const int pieces = static_cast<int>(cut.pieces.size());
    for (const BlobProposal& b : cut.pieces) {
      EXPECT_TRUE(b.piece);
      ASSERT_EQ(b.features.size(), static_cast<std::size_t>(kBlobFeatureCount));
    }
    const bool whole = anyNearly(cut.regions, buoy | panel), on_buoy = anyNearly(cut.pieces, buoy),
               on_panel = anyNearly(cut.pieces, panel);
    if (frame.data == lone.data) {
      EXPECT_EQ(pieces, 0) << "a lone buoy is cut only at its rim";
    } else if (step > 0) {
      EXPECT_TRUE(whole) << "the pair is one region";
      EXPECT_TRUE(on_buoy && on_panel) << pieces << " pieces, on the buoy " << on_buoy << ", on the panel " << on_panel;
    } else {
      EXPECT_EQ(pieces, 0) << "piece_step 0: never cut";
    }
  }
  config.piece_step = -0.1;
  EXPECT_EQ(config.validate().size(), 1u);
  EXPECT_THROW(cutIntoPieces(pair(cv::Rect(0, 0, 64, 48)).clone(), measureWaterContrast(pair, {}), {}, ProposalConfig{}),
               std::invalid_argument) << "contrast of another image";
  EXPECT_THROW(cutIntoPieces(cv::Mat(480, 640, CV_8UC1), measureWaterContrast(pair, {}), {}, ProposalConfig{}),
               std::invalid_argument) << "not BGR";
}

// A buoy against a large panel of another colour: the buoy is cut off as a piece, and so is the rest of their region,
// the panel, though it holds more than kMaxPieceShare of the region's pixels (once a piece is cut off, the rest is an
// object too: before session 49 it was no piece, the region holding the buoy's piece stood for neither, and the panel
// was lost). Also where the buoy, mostly hidden behind a larger panel, holds about 3.5 % of their region's pixels
// (under 5 % it was no piece before session 53, and a small object against a large near one was lost).
TEST(BlobProposals, TheRestOfARegionAPieceWasCutFromIsAPieceToo) {
  struct BuoyBehindPanel {
    cv::Rect panel, buoy;  // the buoy's part left of the panel
    cv::Point centre;      // the buoy's
    int radius;
    double least_share, most_share;  // of the region's pixels that the buoy's piece holds
  };
  const cv::Vec3d water = kWaters[1].veil;
  for (const BuoyBehindPanel& c :
       {BuoyBehindPanel{{300, 160, 160, 120}, {255, 190, 45, 61}, {285, 220}, 30, 0.05, 0.8},
        BuoyBehindPanel{{225, 120, 355, 240}, {180, 195, 45, 91}, {225, 240}, 45, 0.02, 0.05}}) {
    SCOPED_TRACE(testing::Message() << "a buoy of radius " << c.radius << " beside a panel of " << c.panel.size());
    cv::Mat frame = frameWith(water, seen({20, 30, 200}, water, 0.6), c.centre, c.radius, 5);
    frame(c.panel).setTo(cv::Scalar(seen({40, 160, 30}, water, 0.6)));
    ProposalConfig config;
    config.min_area_px = 25;
    const ProposedAndCut cut = proposeAndCut(frame, config);
    const BlobProposal *region = firstNearly(cut.regions, c.buoy | c.panel), *piece = firstNearly(cut.pieces, c.buoy);
    ASSERT_NE(region, nullptr) << "the pair is one region";
    ASSERT_NE(piece, nullptr) << cut.pieces.size() << " pieces, none on the buoy";
    const double share = piece->area_px / region->area_px;
    EXPECT_GE(share, c.least_share);
    EXPECT_LT(share, c.most_share);
    EXPECT_TRUE(anyNearly(cut.pieces, c.panel)) << cut.pieces.size() << " pieces, none on the panel";
  }
}

// The steps that cut pieces are the image's chromaticity's (ln R/G, ln B/G), not its brightness's: an orange and a
// yellow panel side by side (the yellow a little brighter) are cut apart, while one panel lit on its left half and
// shaded on its right (60 %: a step of ln 0.6 in every channel) is not cut along its shading.
TEST(BlobProposals, PiecesFollowChromaticityStepsNotShading) {
  const cv::Vec3d water = kWaters[1].veil;
  const cv::Rect left(200, 180, 120, 120), right(320, 180, 120, 120);
  cv::Mat two_colours = frameWith(water, seen({20, 30, 200}, water, 0.6), {320, 240}, 0, 17);
  two_colours(left).setTo(cv::Scalar(60, 150, 240));   // orange (BGR)
  two_colours(right).setTo(cv::Scalar(80, 215, 220));  // yellow
  cv::Mat shaded = frameWith(water, seen({20, 30, 200}, water, 0.6), {320, 240}, 0, 17);
  shaded(left).setTo(cv::Scalar(60, 150, 240));
  shaded(right).setTo(cv::Scalar(36, 90, 144));  // the same orange at 60 %
  ProposalConfig config;
  config.min_area_px = 25;
  for (const cv::Mat& frame : {two_colours, shaded}) {
    const ProposedAndCut cut = proposeAndCut(frame, config);
    const bool whole = anyNearly(cut.regions, left | right), on_left = anyNearly(cut.pieces, left),
               on_right = anyNearly(cut.pieces, right);
    if (frame.data == two_colours.data) {
      ASSERT_TRUE(whole) << "the two panels are one region";
      EXPECT_TRUE(on_left && on_right) << cut.pieces.size() << " pieces";
    } else {
      ASSERT_TRUE(whole) << "the panel, lit and shaded, is one region";
      EXPECT_TRUE(cut.pieces.empty()) << cut.pieces.size() << " pieces of a panel cut along its shading";
    }
  }
}

// squareDilation gives what cv::dilate gives, on masks of every width (whole SIMD lanes, tails, a single
// pixel) and radii, with blobs touching the edges.
TEST(BlobProposals, SquareDilationEqualsOpenCvs) {
  std::mt19937 rng(7);
  for (int radius : {0, 1, 3, 5}) {
    for (const cv::Size size : {cv::Size(1, 1), cv::Size(3, 2), cv::Size(17, 9), cv::Size(64, 33), cv::Size(97, 40)}) {
      cv::Mat mask(size, CV_8UC1);
      for (int y = 0; y < size.height; ++y) {
        for (int x = 0; x < size.width; ++x) mask.at<std::uint8_t>(y, x) = rng() % 9 == 0 ? 255 : 0;
      }
      cv::Mat expected;
      cv::dilate(mask, expected, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * radius + 1, 2 * radius + 1)));
      const cv::Mat got = squareDilation(mask, radius);
      ASSERT_EQ(got.size(), size);
      EXPECT_EQ(cv::countNonZero(got != expected), 0) << size << " radius " << radius;
    }
  }
}

// shrinkByArea gives cv::resize's INTER_AREA bytes: on its own fast path (power-of-two cells across, rows not
// dividing evenly; the water's 960x600 -> 30x19 among them) and on everything it hands to OpenCV.
TEST(AreaShrink, EqualsOpenCvsInterArea) {
  std::mt19937 rng(11);
  std::vector<std::pair<cv::Mat, cv::Size>> cases;
  cases.emplace_back(cv::Mat(600, 960, CV_8UC3), cv::Size(30, 19));
  cases.emplace_back(cv::Mat(480, 640, CV_8UC3), cv::Size(20, 15));  // whole cells both ways: OpenCV's own path
  cases.emplace_back(cv::Mat(3, 4, CV_8UC3), cv::Size(5, 5));        // larger than the image
  cases.emplace_back(cv::Mat(100, 90, CV_8UC3), cv::Size(30, 19));   // 3-pixel cells
  cases.emplace_back(cv::Mat(100, 64, CV_8UC1), cv::Size(16, 7));    // one channel
  for (int k = 0; k < 200; ++k) {
    const int width = 1 + static_cast<int>(rng() % 40), cell = 1 << (rng() % 7), rows = 1 + static_cast<int>(rng() % 700);
    cases.emplace_back(cv::Mat(rows, width * cell, CV_8UC3), cv::Size(width, 1 + static_cast<int>(rng() % rows)));
  }
  int fast = 0, index = 0;
  for (auto& [image, size] : cases) {
    // Half noise over the whole range, half a flat colour with a little noise (sums near the rounding edges).
    if (index++ % 2) {
      cv::randu(image, 0, 256);
    } else {
      cv::Mat noise(image.size(), image.type());
      cv::randu(noise, 0, 24);
      image.setTo(cv::Scalar(rng() % 232, rng() % 232, rng() % 232));
      image += noise;
    }
    fast += image.type() == CV_8UC3 && size.height < image.rows && image.rows % size.height != 0 &&
            image.cols % size.width == 0 && ((image.cols / size.width) & (image.cols / size.width - 1)) == 0;
    cv::Mat expected;
    cv::resize(image, expected, size, 0, 0, cv::INTER_AREA);
    const cv::Mat got = shrinkByArea(image, size);
    ASSERT_EQ(got.size(), size);
    ASSERT_EQ(got.type(), image.type());
    EXPECT_EQ(cv::norm(got, expected, cv::NORM_INF), 0) << image.size() << " -> " << size;
  }
  EXPECT_GT(fast, 150) << "most cases on the fast path";
  EXPECT_THROW(shrinkByArea(cv::Mat(), cv::Size(3, 3)), std::invalid_argument);
  EXPECT_THROW(shrinkByArea(cv::Mat(10, 10, CV_8UC3), cv::Size(0, 3)), std::invalid_argument);
}
