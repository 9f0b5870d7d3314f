// SPDX-License-Identifier: BSD-3-Clause
// Malformed stereo messages, class by class: each is refused by toStereoInput with a message naming the topic,
// the field and the allowed range, before anything (OpenCV, cv_bridge) can fail on it.
#include <cv_bridge/cv_bridge.h>
#include <gtest/gtest.h>

#include <functional>
#include <limits>

#include "underwater_stereo/ros_glue/calibration_conversions.h"
#include "underwater_stereo/ros_glue/stereo_input.h"

using namespace underwater_stereo;

namespace {

struct Input {
  sensor_msgs::Image left, right;
  sensor_msgs::CameraInfo left_info, right_info;
};

Input goodInput() {
  CameraCalibration c;
  c.width = 96;
  c.height = 64;
  c.K = cv::Matx33d(120, 0, 48, 0, 120, 32, 0, 0, 1);
  c.D = {0.01, -0.02, 0, 0, 0};
  c.P = cv::Matx34d(120, 0, 48, 0, 0, 120, 32, 0, 0, 0, 1, 0);
  Input in;
  in.left_info = ros_glue::toCameraInfo(c);
  c.P(0, 3) = -120 * 0.1;
  in.right_info = ros_glue::toCameraInfo(c);
  const cv::Mat image(64, 96, CV_8UC3, cv::Scalar(90, 80, 40));
  in.left = *cv_bridge::CvImage(std_msgs::Header(), "bgr8", image).toImageMsg();
  in.right = in.left;
  return in;
}

/// toStereoInput's message for `in` spoiled by `spoil`; "" when it is accepted.
std::string refusal(const std::function<void(Input&)>& spoil) {
  Input in = goodInput();
  spoil(in);
  try {
    ros_glue::toStereoInput(in.left, in.left_info, in.right, in.right_info, "/s/left/image_raw", "/s/right/image_raw",
                            0.0, 0.5);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(StereoInputChecks, TheGoodPairAndEveryDistortionVectorLengthTheModelAllowsAreAccepted) {
  EXPECT_EQ(refusal([](Input&) {}), "");
  for (const std::size_t n : {0, 4, 5, 8}) {
    EXPECT_EQ(refusal([n](Input& in) { in.left_info.D.assign(n, 0.01); in.right_info.D.assign(n, 0.01); }), "") << n;
  }
  EXPECT_EQ(refusal([](Input& in) {
              in.left_info.distortion_model = in.right_info.distortion_model = "rational_polynomial";
              in.left_info.D.assign(8, 0.01);
              in.right_info.D.assign(8, 0.01);
            }),
            "");
}

TEST(StereoInputChecks, ImageSizesOutsideTheRangeAreRefusedBeforeAnythingMultipliesThem) {
  auto resize = [](sensor_msgs::Image& m, std::uint32_t w, std::uint32_t h) {
    m.width = w;
    m.height = h;
    m.step = w * 3;
    m.data.assign(static_cast<std::size_t>(m.step) * h, 0);
  };
  for (const auto& [w, h] : std::vector<std::pair<std::uint32_t, std::uint32_t>>{{1, 1}, {1, 1200}, {1920, 1}, {31, 64}, {0, 0}}) {
    const std::string m = refusal([&](Input& in) { resize(in.left, w, h); });
    EXPECT_NE(m.find("/s/left/image_raw: image size " + std::to_string(w) + "x" + std::to_string(h) + " is outside 32..16384"),
              std::string::npos) << m;
  }
  // A width whose bytes per row overflow 32 bits (and a height that would make the buffer absurd): no allocation.
  std::string m = refusal([](Input& in) { in.right.width = 0x80000000U; in.right.step = 16; });
  EXPECT_NE(m.find("/s/right/image_raw: image size 2147483648x64 is outside"), std::string::npos) << m;
  m = refusal([](Input& in) { in.left.height = 4000000000U; });
  EXPECT_NE(m.find("image size 96x4000000000"), std::string::npos) << m;
  // search_scale 0.5: 32 px is the floor; 0.1 would need 160 (tested in the core).
}

TEST(StereoInputChecks, StepAndDataThatDoNotFitTheSizeAreRefused) {
  std::string m = refusal([](Input& in) { in.left.step = 100; });
  EXPECT_NE(m.find("/s/left/image_raw: step 100 is below the 288 bytes of a 96x64 bgr8 row"), std::string::npos) << m;
  m = refusal([](Input& in) { in.right.data.resize(100); });
  EXPECT_NE(m.find("/s/right/image_raw: data has 100 bytes, step x height = 288 x 64 needs 18432"), std::string::npos) << m;
  m = refusal([](Input& in) { in.right.data.resize(20000); });
  EXPECT_NE(m.find("data has 20000 bytes"), std::string::npos) << m;
  m = refusal([](Input& in) { in.left.encoding = ""; });
  EXPECT_NE(m.find("encoding '' is not accepted"), std::string::npos) << m;
  m = refusal([](Input& in) {
    in.left.encoding = "bayer_rggb8";
    in.left.step = 96;
    in.left.data.resize(96 * 64);
    in.left.width = 95;
    in.left.step = 95;
    in.left.data.resize(95 * 64);
  });
  EXPECT_FALSE(m.empty());
}

TEST(StereoInputChecks, ImplausibleCalibrationsAreRefusedNamingTheFieldAndRange) {
  const std::vector<std::pair<std::function<void(Input&)>, std::string>> cases{
      {[](Input& in) { in.right_info.P[3] = -120 * 1e12; }, "baseline"},
      {[](Input& in) { in.right_info.P[3] = -120 * 0.001; }, "outside 0.01..2 m"},
      {[](Input& in) { in.left_info.D = {500, -500, 0, 0, 0}; }, "distortion coefficient 500 is outside -10..10"},
      {[](Input& in) { in.left_info.distortion_model = "equidistant"; }, "/s/left/camera_info: distortion_model 'equidistant' is not supported"},
      {[](Input& in) { in.left_info.distortion_model = "fisheye"; }, "not supported"},
      {[](Input& in) { in.left_info.K[0] = 1e-6; }, "K[0] (fx) = 1e-06 px is outside 50..20000"},
      {[](Input& in) { in.left_info.K[4] = 1e6; }, "K[4] (fy) = 1e+06 px is outside 50..20000"},
      {[](Input& in) { in.left_info.K[2] = 1e9; }, "principal point cx = 1e+09 is outside the image (0..96)"},
      {[](Input& in) { in.right_info.K[5] = -3; }, "principal point cy = -3 is outside the image (0..64)"},
      {[](Input& in) { in.left_info.K[8] = 0; }, "K is not a pinhole matrix"},
      {[](Input& in) { in.left_info.P[7] = 5; }, "P[7] and P[11] must be 0"},
      {[](Input& in) { in.left_info.D.assign(3, 0.0); }, "D has 3 coefficients"},
      {[](Input& in) { in.left_info.D.assign(14, 0.0); }, "D has 14 coefficients"},
      {[](Input& in) { in.left_info.distortion_model = "rational_polynomial"; }, "rational_polynomial needs 8 or none"},
      {[](Input& in) { in.left_info.R = {1, 0, 0, 0, 1, 0, 0, 0, -1}; }, "R is a reflection"},
      {[](Input& in) { in.left_info.R[1] = 0.5; }, "R is not a rotation"},
      {[](Input& in) { in.left_info.D[0] = std::numeric_limits<double>::quiet_NaN(); }, "D contains NaN"},
      {[](Input& in) { in.left_info.width = 97; }, "image is 96x64 but its camera_info is 97x64"},
      {[](Input& in) { in.left_info.P[3] = 4; }, "left P[3] must be 0"},
      {[](Input& in) { in.right_info.P[0] = in.right_info.P[5] = 130; }, "different rectified cameras"},
      {[](Input& in) { in.left_info.binning_x = 2; }, "/s/left/camera_info: binning 2x0"},
      {[](Input& in) { in.right_info.roi.width = 50; in.right_info.roi.height = 40; }, "roi 50x40+0+0: only full-resolution"},
  };
  for (const auto& [spoil, expected] : cases) {
    const std::string m = refusal(spoil);
    EXPECT_NE(m.find(expected), std::string::npos) << "expected '" << expected << "' in: " << (m.empty() ? "(accepted)" : m);
  }
}

TEST(StereoInputChecks, StampsFarApartOrAtTheEndsOfTimeAreHandled) {
  std::string m = refusal([](Input& in) { in.right.header.stamp = ros::Time(4294967295U, 999999999U); });
  EXPECT_NE(m.find("apart"), std::string::npos) << m;
  m = refusal([](Input& in) { in.left.header.stamp = ros::Time(0, 1000000); });
  EXPECT_NE(m.find("0.001000 s apart"), std::string::npos) << m;
}
