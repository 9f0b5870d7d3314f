// SPDX-License-Identifier: BSD-3-Clause
// AravisCamera against Aravis' fake GigE Vision camera, run inside this process on 127.0.0.1: the real
// GVCP/GVSP path over UDP, no hardware.
#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "fake_gv_camera.h"
#include "underwater_stereo/camera/aravis_camera.h"
#include "underwater_stereo/camera/pixel_buffer_pool.h"

using namespace underwater_stereo;

namespace {

/// One in-process fake camera on 127.0.0.1 for the test's lifetime.
class FakeCamera : public test::FakeGvCamera {
 public:
  explicit FakeCamera(const char* serial) : FakeGvCamera("127.0.0.1", serial) {}
};

CameraSettings fakeSettings() {
  CameraSettings s;
  s.id = "127.0.0.1";
  s.exposure_us = 5000;
  s.gain = 0;
  s.trigger_line = "Line0";
  return s;
}

/// Mean grey level of a few frames.
double meanOfFrames(AravisCamera& camera) {
  double sum = 0;
  int got = 0;
  CameraFrame f;
  for (int i = 0; i < 10 && got < 3; ++i) {
    if (camera.next(f, test::scaledMs(1000))) {
      sum += cv::mean(f.image)[0];
      ++got;
    }
  }
  EXPECT_EQ(got, 3);
  return got ? sum / got : 0;
}

}  // namespace

TEST(AravisCamera, StreamsCompleteFramesWithTheConfiguredFormatAndReadsSettingsBack) {
  FakeCamera fake("UWS-T1");
  ASSERT_TRUE(fake.running()) << "could not start a fake camera on 127.0.0.1";
  std::vector<std::string> report;
  AravisCamera camera(fakeSettings(), report);
  EXPECT_NE(camera.description().find("Aravis"), std::string::npos) << camera.description();
  EXPECT_EQ(camera.getString("PixelFormat"), "BayerRG8");
  EXPECT_NEAR(camera.getFloat("ExposureTimeAbs"), 5000, 1);
  EXPECT_EQ(camera.getString("TriggerMode"), "Off");
  EXPECT_GE(report.size(), 5U);
  camera.start();
  CameraFrame f;
  ASSERT_TRUE(camera.next(f, test::scaledMs(2000)));
  EXPECT_EQ(f.encoding, "bayer_rggb8");
  EXPECT_EQ(f.image.type(), CV_8UC1);
  EXPECT_EQ(f.image.size(), cv::Size(512, 512));
  ASSERT_TRUE(f.pixels);
  EXPECT_EQ(f.image.data, f.pixels->data()) << "the image is a view of the one copy a message can take over";
  EXPECT_EQ(f.pixels->size(), 512U * 512U);
  EXPECT_GT(f.device_ns, 0U);
  EXPECT_GT(f.host_ns, 0);
  CameraFrame g;
  ASSERT_TRUE(camera.next(g, test::scaledMs(2000)));
  EXPECT_NE(g.frame_id, f.frame_id);
  camera.stop();
}

TEST(AravisCamera, FramesComeFromRecycledBuffersThatKeepTheirBytesWhileHeldAndSurviveARestart) {
  FakeCamera fake("UWS-T2");
  ASSERT_TRUE(fake.running()) << "could not start a fake camera on 127.0.0.1";
  auto& pool = PixelBufferPool::frames();
  std::vector<std::string> report;
  CameraFrame held;
  cv::Mat held_copy;
  std::uint64_t allocations_streaming = 0;
  {
    AravisCamera camera(fakeSettings(), report);
    camera.start();
    ASSERT_TRUE(camera.next(held, test::scaledMs(2000)));
    held_copy = held.image.clone();
    CameraFrame f;
    for (int i = 0; i < 5; ++i) ASSERT_TRUE(camera.next(f, test::scaledMs(2000)));  // warm-up
    allocations_streaming = pool.allocations();
    int differing = 0;
    for (int i = 0; i < 20; ++i) {  // each frame released when the next replaces it
      ASSERT_TRUE(camera.next(f, test::scaledMs(2000)));
      EXPECT_NE(f.pixels->data(), held.pixels->data()) << "a held frame's buffer is never handed out again";
      differing += cv::norm(f.image, held_copy, cv::NORM_INF) > 0;
    }
    EXPECT_GT(differing, 0) << "the fake's frames change, so the held frame's bytes are tested";
    EXPECT_EQ(cv::norm(held.image, held_copy, cv::NORM_INF), 0) << "the held frame kept its bytes";
    EXPECT_EQ(pool.allocations(), allocations_streaming) << "streamed frames are carried by recycled buffers";
    camera.stop();
  }
  {  // the camera loaded again: its stream buffers and frames reuse the first one's
    AravisCamera camera(fakeSettings(), report);
    camera.start();
    CameraFrame f;
    for (int i = 0; i < 10; ++i) ASSERT_TRUE(camera.next(f, test::scaledMs(2000)));
    camera.stop();
  }
  EXPECT_EQ(pool.allocations(), allocations_streaming);
  EXPECT_EQ(cv::norm(held.image, held_copy, cv::NORM_INF), 0);
}

TEST(AravisCamera, AutoExposureOnACameraWithoutItStreamsAtItsCurrentValueNamingTheFeature) {
  FakeCamera fake("UWS-T0");
  ASSERT_TRUE(fake.running()) << "could not start a fake camera on 127.0.0.1";
  CameraSettings s = fakeSettings();
  s.exposure_us = 5000;
  std::vector<std::string> report;
  { AravisCamera fixed(s, report); }  // leaves the fake camera at 5000 us, gain 0
  s.exposure_us = 0;  // auto: the fake camera has no ExposureAuto
  s.gain = -1;        // auto
  report.clear();
  {
    AravisCamera camera(s, report);
    const bool gain_auto = camera.available("GainAuto");
    ASSERT_EQ(camera.unsupported().size(), gain_auto ? 1U : 2U);
    EXPECT_EQ(camera.unsupported()[0].rfind("ExposureAuto:", 0), 0U) << camera.unsupported()[0];
    EXPECT_NE(camera.unsupported()[0].find("5000 us"), std::string::npos) << camera.unsupported()[0];
    if (!gain_auto) {
      EXPECT_EQ(camera.unsupported()[1].rfind("GainAuto:", 0), 0U) << camera.unsupported()[1];
    }
    EXPECT_NEAR(camera.getFloat("ExposureTimeAbs"), 5000, 1);
    camera.start();
    CameraFrame f;
    EXPECT_TRUE(camera.next(f, test::scaledMs(2000)));
    camera.stop();
  }
  s.exposure_us = 5000;
  s.gain = 0;
  AravisCamera fixed(s, report);
  EXPECT_TRUE(fixed.unsupported().empty());
}

TEST(AravisCamera, ExposureAndGainChangeTheImageAsTheFakeCameraShowsIt) {
  FakeCamera fake("UWS-T2");
  std::vector<std::string> report;
  CameraSettings s = fakeSettings();
  s.exposure_us = 2000;
  // The fake camera draws a Mono8 ramp (x + y + frame) % 255 scaled by 1 + gain + log10(exposure / 10 ms):
  // its mean is about 127 x that scale.
  s.pixel_format = "Mono8";
  auto meanWith = [&](double exposure_us, double gain) {
    s.exposure_us = exposure_us;
    s.gain = gain;
    AravisCamera camera(s, report);
    camera.start();
    return meanOfFrames(camera);
  };
  const double dim = meanWith(2000, 0), bright = meanWith(8000, 0), gained = meanWith(2000, 1);
  EXPECT_NEAR(dim, 127 * (1 + std::log10(0.2)), 0.15 * 127 * (1 + std::log10(0.2)));
  EXPECT_NEAR(bright, 127 * (1 + std::log10(0.8)), 0.15 * 127 * (1 + std::log10(0.8)));
  EXPECT_GT(gained, 1.3 * bright) << "gain 1 at 2 ms is brighter than gain 0 at 8 ms";
}

TEST(AravisCamera, SoftwareAndHardwareTriggerAreConfiguredExplicitlyAndReadBack) {
  FakeCamera fake("UWS-T3");
  std::vector<std::string> report;
  CameraSettings s = fakeSettings();
  s.trigger = TriggerMode::kHardware;
  {
    AravisCamera camera(s, report);
    EXPECT_EQ(camera.getString("TriggerSelector"), "FrameStart");
    EXPECT_EQ(camera.getString("TriggerMode"), "On");
    EXPECT_EQ(camera.getString("TriggerSource"), "Line0");
    EXPECT_EQ(camera.getString("TriggerActivation"), "RisingEdge");
  }
  s.trigger = TriggerMode::kSoftware;
  {
    AravisCamera camera(s, report);
    EXPECT_EQ(camera.getString("TriggerSource"), "Software");
    camera.start();
    CameraFrame f;
    EXPECT_FALSE(camera.next(f, test::scaledMs(300))) << "no trigger, no frame";
    camera.trigger();
    EXPECT_TRUE(camera.next(f, test::scaledMs(2000))) << "one trigger, one frame";
  }
  // A value the camera refuses is a clear error naming the feature.
  s.trigger_line = "Line7";
  s.trigger = TriggerMode::kHardware;
  try {
    AravisCamera refused(s, report);
    FAIL() << "Line7 accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("TriggerSource = Line7"), std::string::npos) << e.what();
  }
}

TEST(AravisCamera, LostPacketsAreCountedAndIncompleteFramesNeverReturned) {
  FakeCamera fake("UWS-T4");
  fake.loseGvspPackets(0.02);
  std::vector<std::string> report;
  CameraSettings s = fakeSettings();
  s.packet_resend = false;  // the fake camera does not resend
  AravisCamera camera(s, report);
  camera.start();
  int complete = 0;
  CameraFrame f;
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(test::scaledMs(4000));
  while (std::chrono::steady_clock::now() < end) {
    if (!camera.next(f, test::scaledMs(500))) continue;
    ++complete;
    EXPECT_EQ(f.image.size(), cv::Size(512, 512));
  }
  const CameraStatistics st = camera.statistics();
  EXPECT_GT(st.failed + st.missing_packets, 0U) << "losses counted";
  EXPECT_EQ(st.completed, static_cast<std::uint64_t>(complete)) << "only complete frames returned";
}

TEST(AravisCamera, AnAbsentCameraIsAClearError) {
  std::vector<std::string> report;
  CameraSettings s = fakeSettings();
  s.id = "127.0.0.1";  // nothing listens
  try {
    AravisCamera camera(s, report);
    FAIL() << "opened a camera that is not there";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open camera '127.0.0.1'"), std::string::npos) << e.what();
  }
  s.pixel_format = "YUV422";
  EXPECT_THROW(AravisCamera(s, report), std::runtime_error);
  EXPECT_EQ(s.validate("left").size(), 1U);
}
