// SPDX-License-Identifier: BSD-3-Clause
// AravisStereoSource with two of Aravis' fake GigE cameras in this process (127.0.0.1 and 127.0.0.2, the
// second added to lo as root), under load: a receiver that is sometimes slow, status() polled continuously
// from another thread. Pairs must reach the callback from one thread at a time, in strictly increasing capture
// time, and every pair formed must be delivered or counted. Also run under ThreadSanitizer (scripts/test).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "fake_gv_camera.h"
#include "underwater_stereo/camera/aravis_stereo_source.h"

using namespace underwater_stereo;

/// Two fake cameras (127.0.0.1 and 127.0.0.2, the second added to lo as root) and a configuration that opens
/// them, on the fake's trigger line.
class TwoFakeCameras : public ::testing::Test {
 protected:
  void SetUp() override {
    if (std::system("ip -o addr show dev lo | grep -q ' 127.0.0.2/' || ip addr add 127.0.0.2/8 dev lo 2>/dev/null") != 0) {
      GTEST_SKIP() << "cannot add 127.0.0.2 to lo (needs root)";
    }
    // Started once 127.0.0.2 exists.
    left_fake.emplace("127.0.0.1", "UWS-L");
    right_fake.emplace("127.0.0.2", "UWS-R");
    ASSERT_TRUE(left_fake->running() && right_fake->running()) << "could not start two fake cameras";
    for (CameraSettings* s : {&config.left, &config.right}) s->trigger_line = "Line0";
    config.left.id = "127.0.0.1";
    config.right.id = "127.0.0.2";
  }

  std::optional<test::FakeGvCamera> left_fake, right_fake;
  AravisStereoConfig config;
};

TEST_F(TwoFakeCameras, PairsArriveInIncreasingCaptureTimeFromOneThreadUnderLoad) {
  for (CameraSettings* s : {&config.left, &config.right}) {
    s->exposure_us = 5000;
    s->gain = 0;
  }
  config.sync = TriggerMode::kFreeRun;  // the two cameras' frames complete pairs on either thread
  config.controls.rate_hz = 40;
  std::mutex mutex;
  std::vector<std::int64_t> stamps;
  std::vector<std::uint64_t> sequences;
  std::atomic<int> inside{0}, concurrent{0};
  AravisStereoSource source(config, [](bool, const std::string&) {});
  source.start([&](const StereoFrame& f) {
    if (inside.fetch_add(1) != 0) ++concurrent;
    {
      std::lock_guard<std::mutex> lock(mutex);
      stamps.push_back(f.capture_time_ns);
      sequences.push_back(f.sequence);
      if (stamps.size() % 10 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(250));  // a slow receiver
    }
    inside.fetch_sub(1);
  });
  std::atomic<bool> polling{true};
  std::atomic<std::uint64_t> polls{0};
  std::thread poller([&] {  // diagnostics asking all the time, as a busy nodelet's timer might
    while (polling) {
      const StereoStatus s = source.status();
      if (std::string(cameraStateName(s.left.state)) == "unknown" || std::string(cameraStateName(s.right.state)) == "unknown") {
        ADD_FAILURE() << "a camera status without a state";
      }
      ++polls;
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(test::scaledMs(6000));
  while (std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::lock_guard<std::mutex> lock(mutex);
    if (stamps.size() >= 120) break;
  }
  polling = false;
  poller.join();
  source.stop();
  const StereoStatus status = source.status();
  std::lock_guard<std::mutex> lock(mutex);
  std::cout << stamps.size() << " pairs delivered, " << status.pairs << " formed, " << status.overflowed
            << " dropped while the receiver was busy, " << status.out_of_order << " out of order, " << status.unpaired
            << " frames unpaired, " << polls.load() << " status polls" << std::endl;
  ASSERT_GE(stamps.size(), 20U) << "too few pairs to judge";
  EXPECT_EQ(concurrent.load(), 0) << "the callback ran on two threads at once";
  for (std::size_t k = 1; k < stamps.size(); ++k) {
    ASSERT_LT(stamps[k - 1], stamps[k]) << "pair " << k << " out of capture order";
    ASSERT_EQ(sequences[k], sequences[k - 1] + 1);
  }
  // Every pair formed was delivered or counted (those still queued when stopped are discarded: at most 4).
  EXPECT_LE(stamps.size() + status.overflowed + status.out_of_order, status.pairs);
  EXPECT_GE(stamps.size() + status.overflowed + status.out_of_order + 4, status.pairs);
}

TEST_F(TwoFakeCameras, IndependentCamerasWithTheirOwnAutoGainReportWhatEachFrameWasTakenWith) {
  config.left.exposure_us = 3000;
  config.right.exposure_us = 7000;  // independent: each as configured
  for (CameraSettings* s : {&config.left, &config.right}) s->gain = -1;  // the fake's GainAuto
  config.controls.exposure_sync = ExposureSync::kIndependent;
  config.controls.rate_hz = 20;
  std::mutex mutex;
  std::vector<std::pair<FrameCapture, FrameCapture>> captures;
  AravisStereoSource source(config, [](bool, const std::string&) {});
  source.start([&](const StereoFrame& f) {
    std::lock_guard<std::mutex> lock(mutex);
    if (f.left_capture && f.right_capture) captures.emplace_back(*f.left_capture, *f.right_capture);
  });
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(test::scaledMs(10000));
  while (std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::lock_guard<std::mutex> lock(mutex);
    if (captures.size() >= 5) break;
  }
  source.stop();
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_GE(captures.size(), 5U);
  for (const auto& [l, r] : captures) {
    EXPECT_NEAR(l.exposure_us, 3000, 1);
    EXPECT_NEAR(r.exposure_us, 7000, 1);
    EXPECT_EQ(l.gain_unit, "raw");
    EXPECT_NE(l.camera.find("UWS-L"), std::string::npos);
    EXPECT_FALSE(l.ptp);
  }
  EXPECT_EQ(left_fake->readRegister(ARV_FAKE_CAMERA_REGISTER_EXPOSURE_TIME_US), 3000U);
  EXPECT_EQ(right_fake->readRegister(ARV_FAKE_CAMERA_REGISTER_EXPOSURE_TIME_US), 7000U);
}

TEST_F(TwoFakeCameras, MasterSlaveAutoGainOnACameraWithoutGainInDbIsReportedUnsupported) {
  config.controls.exposure_sync = ExposureSync::kMasterSlave;
  config.controls.gain = -1;  // auto, but the fake has GainRaw only
  AravisStereoSource source(config, [](bool, const std::string&) {});
  source.start([](const StereoFrame&) {});
  auto noted = [](const CameraStatus& c) {
    for (const auto& u : c.unsupported) {
      if (u.rfind("Gain in dB:", 0) == 0) return true;
    }
    return false;
  };
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(test::scaledMs(10000));
  StereoStatus status = source.status();
  while (std::chrono::steady_clock::now() < end && !(noted(status.left) && noted(status.right))) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    status = source.status();
  }
  source.stop();
  EXPECT_TRUE(noted(status.left)) << "left camera: the held gain is not reported";
  EXPECT_TRUE(noted(status.right)) << "right camera: the held gain is not reported";
}
