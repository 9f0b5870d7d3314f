// SPDX-License-Identifier: BSD-3-Clause
// benchmark_matcher: our semi-global matcher against OpenCV's StereoSGBM (MODE_SGBM_3WAY) on the same bands,
// single-threaded: nanoseconds per matched pixel at 16, 32 and 48 disparities, and whether the disparities agree.
#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <string>

#include "underwater_stereo/detection/sgbm_3way_matcher.h"

namespace {

using namespace underwater_stereo;

/// Best of three timings [ns per pixel with a disparity search] of `repeat` calls of f on a w x h band.
template <typename F>
double nsPerPixel(F&& f, int repeat, int w, int h, int disparities) {
  double best = 1e300;
  for (int round = 0; round < 3; ++round) {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < repeat; ++i) f();
    const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
    best = std::min(best, ns / repeat / (static_cast<double>(w - disparities) * h));
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1) {
    const std::string arg = argv[1];
    const bool help = arg == "--help" || arg == "-h";
    if (!help) std::cerr << "benchmark_matcher: takes no options (got " << arg << ")\n";
    (help ? std::cout : std::cerr)
        << "usage: benchmark_matcher\n  Times Sgbm3WayMatcher and cv::StereoSGBM (3WAY, block 5, the detector's\n"
           "  settings) on 500x300 bands of smooth random texture, OpenCV single-threaded.\n";
    return help ? 0 : 2;
  }
  cv::setNumThreads(1);
  std::cout << "AVX2 matcher: " << (Sgbm3WayMatcher::accelerated() ? "yes" : "no (OpenCV's is used)") << "\n\n"
            << "| disparities | ours [ns/px] | OpenCV [ns/px] | OpenCV / ours | same disparities |\n"
            << "|---|---|---|---|---|\n";
  constexpr int kWidth = 500, kHeight = 300, kRepeat = 20;
  cv::Mat left(kHeight, kWidth, CV_8UC1);
  cv::RNG(1).fill(left, cv::RNG::UNIFORM, 0, 256);
  cv::GaussianBlur(left, left, cv::Size(), 1.5);
  cv::Mat right;
  cv::warpAffine(left, right, cv::Matx23d(1, 0, -7.3, 0, 1, 0), left.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  bool all_same = true;
  for (const int disparities : {16, 32, 48}) {
    SgbmParams p;
    p.num_disparities = disparities;
    p.block_size = 5;
    p.p1 = 8 * 25;
    p.p2 = 32 * 25;
    p.uniqueness_ratio = 5;
    const Sgbm3WayMatcher ours(p);
    const auto opencv = cv::StereoSGBM::create(0, disparities, 5, p.p1, p.p2, 1, 0, 5, 0, 0, cv::StereoSGBM::MODE_SGBM_3WAY);
    cv::Mat a, b;
    const double ours_ns = nsPerPixel([&] { a = ours.compute(left, right); }, kRepeat, kWidth, kHeight, disparities);
    const double opencv_ns = nsPerPixel([&] { opencv->compute(left, right, b); }, kRepeat, kWidth, kHeight, disparities);
    const bool same = cv::countNonZero(a != b) == 0;
    all_same = all_same && same;
    std::cout << "| " << disparities << " | " << std::fixed << std::setprecision(1) << ours_ns << " | " << opencv_ns
              << " | " << std::setprecision(2) << opencv_ns / ours_ns << " | " << (same ? "yes" : "NO") << " |\n";
  }
  return all_same ? 0 : 1;
}
