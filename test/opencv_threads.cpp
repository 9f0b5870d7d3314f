// SPDX-License-Identifier: BSD-3-Clause
// UWS_OPENCV_THREADS=N sets OpenCV's thread count before any test runs. scripts/test sets 1 under
// ThreadSanitizer: OpenCV's parallel loops run on TBB, whose synchronisation TSan cannot see (uninstrumented),
// so they would be reported as races; the detector's own threading (one Detector shared by the nodelet's
// workers, OpenCV single-threaded as the nodelet runs it) is what that run checks.
#include <opencv2/core/utility.hpp>

#include <cstdlib>

namespace {
const bool kOpenCvThreadsSet = [] {
  if (const char* n = std::getenv("UWS_OPENCV_THREADS")) cv::setNumThreads(std::atoi(n));
  return true;
}();
}  // namespace
