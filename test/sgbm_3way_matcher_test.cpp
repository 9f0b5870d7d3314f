// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "underwater_stereo/detection/sgbm_3way_matcher.h"

using namespace underwater_stereo;

namespace {

cv::Mat openCvDisparity(const cv::Mat& left, const cv::Mat& right, const SgbmParams& p) {
  cv::Mat disparity;
  cv::StereoSGBM::create(0, p.num_disparities, p.block_size, p.p1, p.p2, p.disp12_max_diff, 0, p.uniqueness_ratio, 0, 0,
                         cv::StereoSGBM::MODE_SGBM_3WAY)
      ->compute(left, right, disparity);
  return disparity;
}

/// A right view of `left` whose content lies `shift` px further left, with noise on both.
cv::Mat shiftedView(const cv::Mat& left, int shift, std::mt19937& rng, int noise) {
  cv::Mat right(left.size(), CV_8UC1);
  std::uniform_int_distribution<int> n(-noise, noise);
  for (int v = 0; v < left.rows; ++v) {
    for (int u = 0; u < left.cols; ++u) {
      right.at<std::uint8_t>(v, u) = cv::saturate_cast<std::uint8_t>(left.at<std::uint8_t>(v, std::min(left.cols - 1, u + shift)) + n(rng));
    }
  }
  return right;
}

/// Smooth texture (blurred noise), the kind block matching locks onto.
cv::Mat texture(cv::Size size, std::mt19937& rng, double blur) {
  cv::Mat noise(size, CV_8UC1);
  cv::RNG(rng()).fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(noise, noise, cv::Size(), blur);
  cv::normalize(noise, noise, 0, 255, cv::NORM_MINMAX);
  return noise;
}

/// `expect_matches`: the scene must give some disparity (false for bands too narrow to hold a valid column).
void expectSameAsOpenCv(const cv::Mat& left, const cv::Mat& right, const SgbmParams& p, const std::string& what,
                        bool expect_matches = true) {
  const cv::Mat ours = Sgbm3WayMatcher(p).compute(left, right), reference = openCvDisparity(left, right, p);
  ASSERT_EQ(ours.type(), CV_16SC1) << what;
  ASSERT_EQ(ours.size(), reference.size()) << what;
  cv::Mat differs = ours != reference;
  const int n = cv::countNonZero(differs);
  if (n > 0) {
    std::vector<cv::Point> where;
    cv::findNonZero(differs, where);
    FAIL() << what << ": " << n << " of " << ours.total() << " pixels differ, first at " << where[0] << ": "
           << ours.at<short>(where[0]) << " vs OpenCV " << reference.at<short>(where[0]);
  }
  // A matcher that finds nothing would trivially agree on a blank: the scenes here must give disparities.
  if (expect_matches) {
    EXPECT_GT(cv::countNonZero(reference >= 0), 0) << what;
  }
}

/// The penalties RoiStereoMatcher uses (OpenCV's recommended 8 and 32 per block pixel).
SgbmParams pipelineParams(int num_disparities, int block_size, int uniqueness_ratio) {
  SgbmParams p;
  p.num_disparities = num_disparities;
  p.block_size = block_size;
  p.p1 = 8 * block_size * block_size;
  p.p2 = 32 * block_size * block_size;
  p.uniqueness_ratio = uniqueness_ratio;
  return p;
}

}  // namespace

TEST(Sgbm3WayMatcher, SameDisparitiesAsOpenCvOnShiftedTextures) {
  if (!Sgbm3WayMatcher::accelerated()) GTEST_SKIP() << "no AVX2: compute() is OpenCV's own matcher";
  std::mt19937 rng(7);
  for (const int num : {16, 32, 48, 64}) {
    for (const int bs : {3, 5, 11}) {
      for (const int uniqueness : {0, 5, 15}) {
        const cv::Size size(num + 40 + static_cast<int>(rng() % 300), 20 + static_cast<int>(rng() % 120));
        const cv::Mat left = texture(size, rng, 1.0 + (rng() % 3));
        const int shift = static_cast<int>(rng() % num);
        expectSameAsOpenCv(left, shiftedView(left, shift, rng, 4), pipelineParams(num, bs, uniqueness),
                           "num " + std::to_string(num) + " bs " + std::to_string(bs) + " uniqueness " + std::to_string(uniqueness) +
                               " size " + std::to_string(size.width) + "x" + std::to_string(size.height));
      }
    }
  }
}

TEST(Sgbm3WayMatcher, SameDisparitiesAsOpenCvOnNoiseFlatAreasAndTinyImages) {
  if (!Sgbm3WayMatcher::accelerated()) GTEST_SKIP() << "no AVX2: compute() is OpenCV's own matcher";
  std::mt19937 rng(11);
  SgbmParams p;
  p.num_disparities = 32;
  p.p1 = 200;
  p.p2 = 800;
  // Pure noise (costs tie and saturate), a flat grey band with one textured square (ties everywhere), and
  // images so short that OpenCV's stripes start clamped at row 0.
  cv::Mat noise_l(60, 200, CV_8UC1), noise_r(60, 200, CV_8UC1);
  cv::RNG(rng()).fill(noise_l, cv::RNG::UNIFORM, 0, 256);
  cv::RNG(rng()).fill(noise_r, cv::RNG::UNIFORM, 0, 256);
  expectSameAsOpenCv(noise_l, noise_r, p, "noise");
  cv::Mat flat(50, 180, CV_8UC1, cv::Scalar(90));
  texture(cv::Size(40, 30), rng, 1.5).copyTo(flat(cv::Rect(100, 10, 40, 30)));
  expectSameAsOpenCv(flat, shiftedView(flat, 9, rng, 0), p, "flat with a square");
  // A pattern repeating every 8 columns: equal least costs 8 and 16 disparities apart, decided by OpenCV's
  // tie-break (uniqueness would drop them).
  cv::Mat periodic(40, 160, CV_8UC1);
  const cv::Mat tile = texture(cv::Size(8, 40), rng, 0.5);
  for (int u = 0; u < periodic.cols; u += 8) tile.copyTo(periodic(cv::Rect(u, 0, 8, 40)));
  p.uniqueness_ratio = 0;
  expectSameAsOpenCv(periodic, shiftedView(periodic, 3, rng, 0), p, "period 8");
  p.uniqueness_ratio = 5;
  for (const int rows : {5, 8, 12, 17}) {
    const cv::Mat left = texture(cv::Size(120, rows), rng, 1.0);
    expectSameAsOpenCv(left, shiftedView(left, 5, rng, 2), p, std::to_string(rows) + " rows");
  }
  // The largest block saturates 16-bit sums.
  p.block_size = 11;
  p.p1 = 8 * 121;
  p.p2 = 32 * 121;
  expectSameAsOpenCv(noise_l, noise_r, p, "noise, block 11");
}

TEST(Sgbm3WayMatcher, RefusesBadParametersAndImages) {
  SgbmParams p;
  p.num_disparities = 24;
  p.block_size = 4;
  p.p2 = p.p1;
  try {
    Sgbm3WayMatcher bad(p);
    FAIL() << "accepted bad parameters";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("num_disparities"), std::string::npos) << what;
    EXPECT_NE(what.find("block_size"), std::string::npos) << what;
    EXPECT_NE(what.find("p1 < p2"), std::string::npos) << what;
  }
  const Sgbm3WayMatcher matcher{SgbmParams()};
  const cv::Mat grey(20, 100, CV_8UC1, cv::Scalar(0));
  EXPECT_THROW(matcher.compute(grey, cv::Mat(20, 101, CV_8UC1)), std::invalid_argument);
  EXPECT_THROW(matcher.compute(grey, cv::Mat(20, 100, CV_8UC3)), std::invalid_argument);
  EXPECT_THROW(matcher.compute(grey(cv::Rect(0, 0, 20, 20)), grey(cv::Rect(0, 0, 20, 20))), std::invalid_argument);
  EXPECT_THROW(matcher.compute(cv::Mat(), cv::Mat()), std::invalid_argument);
}

// More than 64 disparities: the AVX2 matcher keeps its path costs in memory (matchRow<0>) instead of registers.
// The pipeline searches that many when the silhouette is not found (the whole workspace: 0.5-5 m is ~400
// disparities with f = 1820 px and B = 0.12 m) and for near objects. With UWS_PORTABLE_MATCHER=1 (or without
// AVX2) compute() is OpenCV's own matcher: these then check that it is called with the same parameters.
TEST(Sgbm3WayMatcher, SameDisparitiesAsOpenCvBeyond64DisparitiesUpToTheWorkspace) {
  const unsigned seed = 13;
  std::mt19937 rng(seed);
  for (const int num : {80, 96, 128, 208, 400, 416, 512}) {
    for (const int bs : {3, 5, 11}) {
      const int uniqueness = std::vector<int>{0, 5, 15}[rng() % 3];
      const cv::Size size(num + 40 + static_cast<int>(rng() % 300), 12 + static_cast<int>(rng() % 60));
      const cv::Mat left = texture(size, rng, 1.0 + (rng() % 3));
      const int shift = static_cast<int>(rng() % num);
      expectSameAsOpenCv(left, shiftedView(left, shift, rng, 4), pipelineParams(num, bs, uniqueness),
                         "seed " + std::to_string(seed) + " num " + std::to_string(num) + " bs " + std::to_string(bs) +
                             " uniqueness " + std::to_string(uniqueness) + " shift " + std::to_string(shift) + " size " +
                             std::to_string(size.width) + "x" + std::to_string(size.height));
    }
  }
}

// The band widths RoiStereoMatcher hands over: the narrowest a search fits in (num + block + 1, where it clips
// the disparities near the image's left edge) and up to 15 px wider, an object's band, and a whole
// 1920-px row; heights from one block to a tall object.
TEST(Sgbm3WayMatcher, SameDisparitiesAsOpenCvAtTheBandWidthsThePipelineUses) {
  const unsigned seed = 17;
  std::mt19937 rng(seed);
  const int bs = 5;
  for (const int num : {16, 64, 80, 400}) {
    for (const int width : {num + bs + 1, num + bs + 8, num + bs + 16, num + 24 + 250, 1920}) {
      for (const int rows : {bs, 37}) {
        const cv::Mat left = texture(cv::Size(width, rows), rng, 1.5);
        const int shift = static_cast<int>(rng() % num);
        expectSameAsOpenCv(left, shiftedView(left, shift, rng, 3), pipelineParams(num, bs, 5),
                           "seed " + std::to_string(seed) + " num " + std::to_string(num) + " width " +
                               std::to_string(width) + " rows " + std::to_string(rows),
                           width >= num + 2 * bs + 16 && rows > bs);
      }
    }
  }
}
