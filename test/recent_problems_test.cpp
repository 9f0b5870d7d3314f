// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include "underwater_stereo/ros_glue/recent_problems.h"

using namespace underwater_stereo::ros_glue;

TEST(RecentProblems, TwoKindsWithinTheHoldAreBothNamedNewestFirst) {
  RecentProblems p(5.0, 3);
  EXPECT_EQ(p.summary(0.0), "");
  p.add("image size 1x1", 10.0);
  p.add("stamps 50 ms apart", 10.1);  // refused by another worker just after
  EXPECT_EQ(p.summary(11.0), "stamps 50 ms apart; image size 1x1");
  EXPECT_EQ(p.last(), "stamps 50 ms apart");
  EXPECT_EQ(p.count(), 2);
}

TEST(RecentProblems, ARepeatedProblemIsNamedOnceAndOldOnesLeaveTheSummaryButStayTheLast) {
  RecentProblems p(5.0, 3);
  p.add("a", 0.0);
  p.add("b", 1.0);
  p.add("a", 2.0);
  EXPECT_EQ(p.summary(2.0), "a; b");
  EXPECT_EQ(p.summary(6.5), "a") << "b was last seen 5.5 s ago";
  EXPECT_EQ(p.summary(7.0), "");
  EXPECT_EQ(p.last(), "a");
  EXPECT_EQ(p.count(), 3);
}

TEST(RecentProblems, BeyondMaxKindsTheRestAreCounted) {
  RecentProblems p(5.0, 2);
  for (const char* w : {"a", "b", "c", "d"}) p.add(w, 1.0);
  EXPECT_EQ(p.summary(1.0), "d; c; and 2 more");
}
