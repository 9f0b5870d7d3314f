// SPDX-License-Identifier: BSD-3-Clause
// The StereoCameraNodelet on the real Aravis GigE path: this test runs two of Aravis' fake GigE Vision
// cameras in its own process on 127.0.0.1 and 127.0.0.2 (created after the nodelet started, so it must wait
// for them), checks the pairs, then takes the right camera away and brings it back (first without its stream),
// and loses packets.
#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <algorithm>
#include <cstdlib>
#include <iterator>
#include <map>
#include <mutex>
#include <vector>

#include "diagnostics_helpers.h"
#include "fake_gv_camera.h"
#include "ros_test_helpers.h"

namespace {

using FakeCamera = underwater_stereo::test::FakeGvCamera;
using underwater_stereo::test::waitFor;

struct Received {
  std::mutex mutex;
  std::map<ros::Time, sensor_msgs::ImageConstPtr> left, right;
  std::map<ros::Time, sensor_msgs::CameraInfoConstPtr> left_info;
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> diagnostics;  ///< latest per name

  int pairsSince(const ros::Time& t) {
    std::lock_guard<std::mutex> lock(mutex);
    int n = 0;
    for (auto it = left.lower_bound(t); it != left.end(); ++it) n += right.count(it->first);
    return n;
  }
  diagnostic_msgs::DiagnosticStatus diagnostic(const std::string& suffix) {
    std::lock_guard<std::mutex> lock(mutex);
    return underwater_stereo::test::statusEndingWith(diagnostics, suffix);
  }
};

using underwater_stereo::test::value;

}  // namespace

TEST(StereoCameraAravis, PairsFromTwoFakeGigECamerasSurviveALostCameraAndLostPackets) {
  // The second camera needs its own loopback address (the fake binds its control port per address).
  ASSERT_EQ(std::system("ip -o addr show dev lo | grep -q ' 127.0.0.2/' || ip addr add 127.0.0.2/8 dev lo"), 0)
      << "cannot add 127.0.0.2 to lo (needs root)";
  ros::NodeHandle nh("stereo");
  Received rx;
  auto s1 = nh.subscribe<sensor_msgs::Image>("left/image_raw", 50, [&](const sensor_msgs::ImageConstPtr& m) {
    std::lock_guard<std::mutex> lock(rx.mutex);
    rx.left[m->header.stamp] = m;
  });
  auto s2 = nh.subscribe<sensor_msgs::Image>("right/image_raw", 50, [&](const sensor_msgs::ImageConstPtr& m) {
    std::lock_guard<std::mutex> lock(rx.mutex);
    rx.right[m->header.stamp] = m;
  });
  auto s3 = nh.subscribe<sensor_msgs::CameraInfo>("left/camera_info", 50, [&](const sensor_msgs::CameraInfoConstPtr& m) {
    std::lock_guard<std::mutex> lock(rx.mutex);
    rx.left_info[m->header.stamp] = m;
  });
  auto s4 = nh.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 50,
                                                            [&](const diagnostic_msgs::DiagnosticArrayConstPtr& m) {
                                                              std::lock_guard<std::mutex> lock(rx.mutex);
                                                              for (const auto& s : m->status) rx.diagnostics[s.name] = s;
                                                            });
  ros::AsyncSpinner spinner(2);
  spinner.start();

  // Absent at start-up: the nodelet waits and reports it.
  EXPECT_TRUE(waitFor(
      [&] {
        const auto d = rx.diagnostic("left camera");
        return d.level == diagnostic_msgs::DiagnosticStatus::ERROR &&
               d.message.find("cannot open camera '127.0.0.1'") != std::string::npos;
      },
      20.0))
      << "absent camera not reported: " << rx.diagnostic("left camera").message;

  auto left = std::make_unique<FakeCamera>("127.0.0.1", "FAKE-LEFT");
  auto right = std::make_unique<FakeCamera>("127.0.0.2", "FAKE-RIGHT");
  ASSERT_TRUE(left->running() && right->running()) << "the fake cameras did not start";

  // Pairs at the configured 10 Hz with identical stamps, the right encoding, size and camera_info.
  ASSERT_TRUE(waitFor([&] { return rx.pairsSince(ros::Time(0)) >= 5; }, 25.0)) << "no pairs after the cameras came";
  const ros::Time start = ros::Time::now();
  ros::WallDuration(3.0).sleep();
  {
    const int pairs = rx.pairsSince(start);
    std::lock_guard<std::mutex> lock(rx.mutex);
    int lefts = 0;
    for (auto it = rx.left.lower_bound(start); it != rx.left.end(); ++it) ++lefts;
    // The configured rate reached the cameras: the median spacing of the capture stamps, not the wall-clock
    // count (a loaded machine delays or drops frames; throughput belongs in a benchmark, not here).
    std::vector<double> gaps;
    for (auto it = rx.left.lower_bound(start); it != rx.left.end() && std::next(it) != rx.left.end(); ++it) {
      gaps.push_back((std::next(it)->first - it->first).toSec());
    }
    ASSERT_GE(pairs, 3) << "pairs in 3 s";
    std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
    EXPECT_NEAR(gaps[gaps.size() / 2], 0.1, 0.03) << "median spacing of the left stamps at rate_hz 10";
    EXPECT_GE(pairs, lefts - 1) << "every left image has a right one with the identical stamp";
    const auto& img = *rx.left.rbegin()->second;
    EXPECT_EQ(img.encoding, "bayer_rggb8");
    EXPECT_EQ(img.width, 512U);
    EXPECT_EQ(img.height, 512U);
    EXPECT_EQ(img.header.frame_id, "stereo_left_optical_frame");
    ASSERT_FALSE(rx.left_info.empty());
    EXPECT_EQ(rx.left_info.rbegin()->second->width, 512U);
    EXPECT_LT(std::abs((rx.left.rbegin()->first - ros::Time::now()).toSec()), 1.0) << "stamps are capture times";
  }
  EXPECT_EQ(rx.diagnostic("left camera").level, diagnostic_msgs::DiagnosticStatus::OK);
  EXPECT_NE(value(rx.diagnostic("left camera"), "camera").find("FAKE-LEFT"), std::string::npos);

  // The right camera vanishes: no pairs, the diagnostic shows the outage; it comes back: pairs resume in 10 s.
  right.reset();
  ASSERT_TRUE(waitFor([&] { return rx.diagnostic("right camera").level == diagnostic_msgs::DiagnosticStatus::ERROR; }, 10.0))
      << "the outage is not shown: " << rx.diagnostic("right camera").message;
  const ros::Time gone = ros::Time::now();
  ros::WallDuration(1.0).sleep();
  EXPECT_EQ(rx.pairsSince(gone + ros::Duration(0.5)), 0) << "pairs without a right camera";
  // It comes back answering its control port but its stream lost (every packet dropped): not back yet, the
  // nodelet retries with back-off and the outage stays one.
  right = std::make_unique<FakeCamera>("127.0.0.2", "FAKE-RIGHT");
  right->loseGvspPackets(1.0);
  EXPECT_TRUE(waitFor(
      [&] { return rx.diagnostic("right camera").message.find("opened, but no frame") != std::string::npos; },
      10.0))
      << "a camera without a stream is not shown: " << rx.diagnostic("right camera").message;
  ros::WallDuration(2.0).sleep();
  EXPECT_EQ(rx.pairsSince(gone + ros::Duration(0.5)), 0) << "pairs without the right camera's stream";
  right->loseGvspPackets(0.0);
  const ros::Time back = ros::Time::now();
  EXPECT_TRUE(waitFor([&] { return rx.pairsSince(back) >= 3; }, 10.0)) << "pairs did not resume within 10 s";
  EXPECT_TRUE(waitFor([&] { return value(rx.diagnostic("right camera"), "outages") == "1"; }, 3.0))
      << "outages: " << value(rx.diagnostic("right camera"), "outages");
  EXPECT_EQ(value(rx.diagnostic("left camera"), "outages"), "0") << "the left camera kept streaming";

  // Lost packets: counted, and the pairs that still come are complete.
  left->loseGvspPackets(0.01);
  right->loseGvspPackets(0.01);
  const ros::Time lossy = ros::Time::now();
  EXPECT_TRUE(waitFor(
      [&] {
        const auto l = rx.diagnostic("left camera");
        return std::atoll(value(l, "failed (incomplete) buffers").c_str()) +
                   std::atoll(value(l, "missing packets").c_str()) > 0;
      },
      10.0))
      << "losses not counted";
  {
    std::lock_guard<std::mutex> lock(rx.mutex);
    for (auto it = rx.left.lower_bound(lossy); it != rx.left.end(); ++it) {
      EXPECT_EQ(it->second->data.size(), 512U * 512U) << "a frame was published incomplete";
    }
  }
  spinner.stop();
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "stereo_camera_aravis_test");
  return RUN_ALL_TESTS();
}
