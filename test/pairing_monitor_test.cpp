// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <thread>

#include "underwater_stereo/ros_glue/pairing_monitor.h"

using namespace underwater_stereo::ros_glue;

TEST(PairingMonitor, AnImageNeverPairedIsCountedOnceItCanNoLongerPairWithTheNearestStampDifference) {
  PairingMonitor m(3);
  // Pairs 1..4 complete; the left image 5 has a right partner 1 ms off (exact sync never pairs it).
  for (int i = 1; i <= 4; ++i) {
    m.image(StereoSide::kLeft, i);
    m.image(StereoSide::kRight, i);
    m.paired(i, i);
  }
  m.image(StereoSide::kLeft, 5.0);
  m.image(StereoSide::kRight, 5.001);
  EXPECT_EQ(m.counts().unpaired_left, 0) << "still pairable";
  for (int i = 6; i <= 8; ++i) m.image(StereoSide::kLeft, i);  // the left 5 leaves the synchroniser's window
  PairingMonitor::Counts c = m.counts();
  EXPECT_EQ(c.unpaired_left, 1);
  EXPECT_EQ(c.last, "left image 5.000000 never paired: the nearest right image is +1.000 ms away");
  for (int i = 6; i <= 8; ++i) {
    m.image(StereoSide::kRight, i);
    m.paired(i, i);
  }
  c = m.counts();
  EXPECT_EQ(c.unpaired_left, 1);
  EXPECT_EQ(c.unpaired_right, 1);
  EXPECT_NE(c.last.find("right image 5.001000 never paired"), std::string::npos) << c.last;
}

TEST(PairingMonitor, ALeftImageWithoutAnyRightImageIsCounted) {
  PairingMonitor m(2);
  for (int i = 0; i < 5; ++i) m.image(StereoSide::kLeft, i);
  const PairingMonitor::Counts c = m.counts();
  EXPECT_EQ(c.unpaired_left, 3);
  EXPECT_EQ(c.unpaired_right, 0);
  EXPECT_NE(c.last.find("no right image seen near it"), std::string::npos) << c.last;
}

TEST(PairingMonitor, ConcurrentCallersCountEveryImage) {
  PairingMonitor m(4);
  std::thread left([&] {
    for (int i = 0; i < 10000; ++i) m.image(StereoSide::kLeft, i);
  });
  std::thread right([&] {
    for (int i = 0; i < 10000; ++i) m.image(StereoSide::kRight, i + 0.5);
  });
  left.join();
  right.join();
  const PairingMonitor::Counts c = m.counts();
  EXPECT_EQ(c.unpaired_left, 10000 - 4);
  EXPECT_EQ(c.unpaired_right, 10000 - 4);
}
