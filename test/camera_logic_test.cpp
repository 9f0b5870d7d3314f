// SPDX-License-Identifier: BSD-3-Clause
// The camera logic that needs no camera: pairing, frame-id gaps, clock mapping, feature-name fallback, trigger
// schedule.
#include <gtest/gtest.h>

#include <map>
#include <string>
#include <vector>
#include <random>

#include "underwater_stereo/camera/camera_controls.h"
#include "underwater_stereo/camera/clock_mapper.h"
#include "underwater_stereo/camera/frame_id_tracker.h"
#include "underwater_stereo/camera/frame_pairer.h"
#include "underwater_stereo/camera/genicam_features.h"
#include "underwater_stereo/camera/trigger_schedule.h"

using namespace underwater_stereo;

TEST(FramePairer, PairsByCaptureTimeAndCountsFramesLeftWithoutAPartner) {
  using Pairer = FramePairer<int>;
  Pairer p(1'000'000);  // 1 ms
  const std::int64_t period = 66'666'667;  // 15 Hz
  int pairs = 0;
  for (int k = 0; k < 10; ++k) {
    const std::int64_t t = k * period;
    if (k == 4) {  // the right frame of pair 4 is lost
      EXPECT_FALSE(p.add(Pairer::kLeft, t, k));
      continue;
    }
    EXPECT_FALSE(p.add(Pairer::kLeft, t + 200'000, k));  // left 0.2 ms late
    const auto pair = p.add(Pairer::kRight, t, 100 + k);
    ASSERT_TRUE(pair) << k;
    EXPECT_EQ(pair->first, k);
    EXPECT_EQ(pair->second, 100 + k);
    ++pairs;
  }
  EXPECT_EQ(pairs, 9);
  EXPECT_EQ(p.dropped(), 1U);  // left 4, once right 5 arrived
  ASSERT_TRUE(p.lastMiss());
  EXPECT_EQ(p.lastMiss()->side, Pairer::kLeft);
  EXPECT_EQ(p.lastMiss()->time_ns, 4 * period);
  EXPECT_TRUE(p.lastMiss()->other_seen);
  EXPECT_EQ(p.lastMiss()->other_minus_this_ns, period) << "the right frame that made it hopeless: right 5";
  EXPECT_EQ(p.waiting(Pairer::kLeft) + p.waiting(Pairer::kRight), 0U);
}

TEST(FramePairer, FramesOutsideTheSkewNeverPairAndWaitingIsBounded) {
  using Pairer = FramePairer<int>;
  Pairer p(1'000'000, 3);
  EXPECT_FALSE(p.add(Pairer::kLeft, 0, 0));
  EXPECT_FALSE(p.add(Pairer::kRight, 5'000'000, 1)) << "5 ms apart";
  EXPECT_EQ(p.dropped(), 1U) << "left 0 can no longer pair";
  ASSERT_TRUE(p.lastMiss());
  EXPECT_EQ(p.lastMiss()->side, Pairer::kLeft);
  EXPECT_EQ(p.lastMiss()->other_minus_this_ns, 5'000'000) << "the stamp difference seen";
  for (int k = 0; k < 6; ++k) p.add(Pairer::kRight, 10'000'000 + k * 100'000'000LL, k);
  EXPECT_EQ(p.waiting(Pairer::kRight), 3U);
  EXPECT_EQ(p.lastMiss()->side, Pairer::kRight);
  EXPECT_EQ(p.lastMiss()->time_ns, 210'000'000) << "the oldest right frame, pushed out";
  EXPECT_FALSE(p.lastMiss()->other_seen) << "no left frame was waiting";
  EXPECT_EQ(p.pairs(), 0U);
  p.setMaxSkewNs(10'000'000);  // a slower free-run rate: half its period
  EXPECT_TRUE(p.add(Pairer::kLeft, 510'000'000 + 6'000'000, 9)) << "6 ms from right 5: within the new 10 ms";
  EXPECT_EQ(p.pairs(), 1U);
}

TEST(TriggerSchedule, TicksHalfAPeriodOffTheWallClocksMultiplesAndFollowAClockStep) {
  const TriggerSchedule at15(15.0);
  EXPECT_EQ(at15.periodUs(), 66'667) << "whole microseconds";
  const std::int64_t base = 1'796'000'000LL * 1'000'000 / 66'667 * 66'667;  // a multiple of the period
  EXPECT_EQ(at15.nextAfter(base), base + 33'333);
  EXPECT_EQ(at15.nextAfter(base + 33'332), base + 33'333);
  EXPECT_EQ(at15.nextAfter(base + 33'333), base + 33'333 + 66'667) << "strictly after";
  EXPECT_EQ(at15.nextAfter(-1), 33'333);
  EXPECT_EQ(at15.nextAfter(-40'000), 33'333 - 66'667) << "before the epoch too";
  // The same ticks from anywhere in between, so two threads agree.
  for (std::int64_t now = base + 40'000; now < base + 100'000; now += 7'001) {
    EXPECT_EQ(at15.nextAfter(now), base + 33'333 + 66'667);
  }
  const std::int64_t tick = base + 33'333;
  EXPECT_EQ(at15.keepOrRenew(tick, base + 1'000), tick) << "still ahead";
  EXPECT_EQ(at15.keepOrRenew(tick, tick), tick + 66'667) << "reached: the next";
  EXPECT_EQ(at15.keepOrRenew(tick, tick + 10 * 66'667 + 5), tick + 11 * 66'667) << "clock stepped forward: no burst";
  EXPECT_EQ(at15.keepOrRenew(tick, tick - 5'000'000), at15.nextAfter(tick - 5'000'000)) << "clock stepped back";
  EXPECT_EQ(TriggerSchedule(1e6).periodUs(), 1);
  EXPECT_THROW(TriggerSchedule(0.0), std::invalid_argument);
  EXPECT_THROW(TriggerSchedule(-1.0), std::invalid_argument);
}

TEST(FrameIdTracker, CountsGapsAcrossThe16BitWrapSkippingZero) {
  FrameIdTracker t;
  EXPECT_EQ(t.missedBefore(65533), 0U);  // first
  EXPECT_EQ(t.missedBefore(65534), 0U);
  EXPECT_EQ(t.missedBefore(65535), 0U);
  EXPECT_EQ(t.missedBefore(1), 0U) << "65535 -> 1: 0 is never used";
  EXPECT_EQ(t.missedBefore(4), 2U);
  EXPECT_EQ(t.missedBefore(65534 + 65536), 0U) << "taken modulo 65536: a jump backwards, restart";
  EXPECT_EQ(t.missedBefore(3), 3U) << "65534 -> 3 misses 65535, 1, 2";
  EXPECT_EQ(t.missedBefore(3), 0U) << "repeated";
  EXPECT_EQ(t.totalMissed(), 5U);
  EXPECT_EQ(t.missedBefore(0), 0U);
  EXPECT_EQ(t.missedBefore(9), 0U) << "after 0: restart";
}

TEST(ClockMapper, RemovesTransferJitterAndFollowsACameraRestart) {
  ClockMapper m(32);
  std::mt19937 rng(3);
  std::exponential_distribution<double> delay(1.0 / 2e6);  // 2 ms mean transfer delay
  const std::int64_t offset = 1'700'000'000'000'000'000LL;
  double worst = 0, worst_raw = 0;
  for (int k = 0; k < 200; ++k) {
    const std::uint64_t device = 1'000'000'000ULL + k * 66'666'667ULL;
    const std::int64_t host = offset + static_cast<std::int64_t>(device) + 300'000 + static_cast<std::int64_t>(delay(rng));
    const std::int64_t mapped = m.toHost(device, host);
    const std::int64_t truth = offset + static_cast<std::int64_t>(device) + 300'000;
    if (k >= 32) {
      worst = std::max(worst, std::abs(double(mapped - truth)));
      worst_raw = std::max(worst_raw, std::abs(double(host - truth)));
    }
  }
  EXPECT_LT(worst, 500'000) << "within 0.5 ms of capture + minimum delay";
  EXPECT_GT(worst_raw, 5'000'000) << "receive times alone jitter by more than 5 ms";
  // Restart: the device clock starts again near 0.
  const std::int64_t host = offset + 50'000'000'000LL;
  EXPECT_EQ(m.toHost(5'000'000, host), host);
  EXPECT_EQ(m.toHost(0, 1234), 1234) << "no device timestamp: host time";
  EXPECT_THROW(ClockMapper(0), std::invalid_argument);
}

namespace {

/// Features held in maps; a camera of one generation or another.
class MapCamera : public FeatureAccess {
 public:
  std::map<std::string, double> floats;
  std::map<std::string, double> max;
  std::map<std::string, std::string> strings;
  bool available(const std::string& n) const override { return floats.count(n) || strings.count(n); }
  void setFloat(const std::string& n, double v) override {
    floats.at(n) = max.count(n) ? std::min(v, max.at(n)) : v;  // clamps, as cameras do
  }
  double getFloat(const std::string& n) const override { return floats.at(n); }
  void setInteger(const std::string& n, long v) override { floats.at(n) = double(v); }
  long getInteger(const std::string& n) const override { return long(floats.at(n)); }
  void setString(const std::string& n, const std::string& v) override {
    if (v == "Bad") throw std::runtime_error("not an entry");
    strings.at(n) = v;
  }
  std::string getString(const std::string& n) const override { return strings.at(n); }
  void setBoolean(const std::string& n, bool v) override { floats.at(n) = v; }
  bool getBoolean(const std::string& n) const override { return floats.at(n) != 0; }
  void execute(const std::string& n) override { executed.push_back(n); }
  std::vector<std::string> executed;
};

}  // namespace

TEST(GenicamFeatures, FallsBackBetweenFeatureNamesAndReportsRefusedValues) {
  MapCamera older;  // e.g. a Basler of the GigE generation: ...Abs names, raw gain
  older.floats = {{"ExposureTimeAbs", 1000}, {"GainRaw", 0}, {"AcquisitionFrameRateAbs", 10}};
  older.max = {{"AcquisitionFrameRateAbs", 50}};
  EXPECT_EQ(firstAvailable(older, {"ExposureTime", "ExposureTimeAbs"}), "ExposureTimeAbs");
  EXPECT_DOUBLE_EQ(setFloatFeature(older, {"ExposureTime", "ExposureTimeAbs"}, 5000), 5000);
  EXPECT_DOUBLE_EQ(older.floats["ExposureTimeAbs"], 5000);
  EXPECT_DOUBLE_EQ(setFloatFeature(older, {"AcquisitionFrameRate", "AcquisitionFrameRateAbs"}, 15), 15);
  try {
    setFloatFeature(older, {"AcquisitionFrameRate", "AcquisitionFrameRateAbs"}, 80);
    FAIL() << "a clamped value must be an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("AcquisitionFrameRateAbs = 80"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("reads 50"), std::string::npos) << e.what();
  }
  try {
    firstAvailable(older, {"Gain", "GainDb"});
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("none of the features Gain GainDb"), std::string::npos) << e.what();
  }
  MapCamera newer;
  newer.strings = {{"TriggerMode", "Off"}};
  setStringFeature(newer, "TriggerMode", "On");
  EXPECT_EQ(newer.strings["TriggerMode"], "On");
  EXPECT_THROW(setStringFeature(newer, "TriggerMode", "Bad"), std::runtime_error);
  EXPECT_THROW(setStringFeature(newer, "TriggerSource", "Line1"), std::runtime_error);
}

TEST(CameraControls, ExposureAndGainByWhicheverNamesTheCameraHasAutoSwitchedOff) {
  MapCamera older;  // GigE generation: ExposureTimeAbs, GainRaw, GainAuto
  older.floats = {{"ExposureTimeAbs", 1000}, {"GainRaw", 0}};
  older.strings = {{"GainAuto", "Continuous"}};
  EXPECT_DOUBLE_EQ(setExposureUs(older, 4000), 4000);
  EXPECT_FALSE(gainInDb(older));
  EXPECT_DOUBLE_EQ(setGain(older, 3.4), 3) << "raw units, rounded";
  EXPECT_EQ(older.strings["GainAuto"], "Off");
  EXPECT_DOUBLE_EQ(gain(older), 3);
  MapCamera newer;  // SFNC: ExposureTime, Gain [dB], ExposureAuto
  newer.floats = {{"ExposureTime", 1000}, {"Gain", 0}};
  newer.max = {{"ExposureTime", 10000}};
  newer.strings = {{"ExposureAuto", "Continuous"}};
  EXPECT_DOUBLE_EQ(setExposureUs(newer, 8000), 8000);
  EXPECT_EQ(newer.strings["ExposureAuto"], "Off");
  EXPECT_TRUE(gainInDb(newer));
  EXPECT_DOUBLE_EQ(setGain(newer, 6.5), 6.5);
  EXPECT_THROW(setExposureUs(newer, 20000), std::runtime_error) << "clamped to 10000 by the camera: refused";
}

TEST(CameraControls, PtpEnabledByEitherNameStateLatchedWhereNeededAbsentReported) {
  MapCamera none;
  none.floats = {{"ExposureTime", 1000}};
  EXPECT_EQ(enablePtp(none), "");
  EXPECT_EQ(ptpStatus(none), "");
  EXPECT_FALSE(ptpSettled(""));
  MapCamera sfnc;
  sfnc.floats = {{"PtpEnable", 0}, {"PtpDataSetLatch", 0}};
  sfnc.strings = {{"PtpStatus", "Listening"}};
  EXPECT_EQ(enablePtp(sfnc), "PtpEnable");
  EXPECT_EQ(sfnc.floats["PtpEnable"], 1);
  EXPECT_EQ(ptpStatus(sfnc), "Listening");
  EXPECT_EQ(sfnc.executed, std::vector<std::string>{"PtpDataSetLatch"});
  EXPECT_FALSE(ptpSettled("Listening"));
  sfnc.strings["PtpStatus"] = "Slave";
  EXPECT_TRUE(ptpSettled(ptpStatus(sfnc)));
  MapCamera gige;  // older Basler/FLIR: GevIEEE1588, GevIEEE1588Status
  gige.floats = {{"GevIEEE1588", 0}};
  gige.strings = {{"GevIEEE1588Status", "Master"}};
  EXPECT_EQ(enablePtp(gige), "GevIEEE1588");
  EXPECT_TRUE(ptpSettled(ptpStatus(gige)));
  EXPECT_TRUE(gige.executed.empty());
}
