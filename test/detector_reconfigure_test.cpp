// SPDX-License-Identifier: BSD-3-Clause
// cfg/DetectorTuning.cfg against detectorTunables(): same names, types, ranges and descriptions; the mapping
// both ways by the table.
#include <gtest/gtest.h>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/ros_glue/detector_reconfigure.h"

using namespace underwater_stereo;

TEST(DetectorReconfigure, CfgAndTableAgreeOnEveryParameter) {
  const auto problems = ros_glue::reconfigureTableProblems();
  EXPECT_TRUE(problems.empty()) << joinProblems("cfg/DetectorTuning.cfg and detectorTunables() disagree", problems);
}

TEST(DetectorReconfigure, EveryReconfigurableValueGoesThereAndBack) {
  DetectorConfig c;
  int changed = 0;
  for (const DetectorTunable& t : detectorTunables()) {
    if (!t.reconfigure) continue;
    t.set(c, t.integer ? std::floor((t.min + t.max) / 3) : (2 * t.min + t.max) / 3);  // inside, not a default
    ++changed;
  }
  ASSERT_EQ(changed, 14);
  DetectorTuningConfig r;
  ros_glue::toReconfigure(c, r);
  const DetectorConfig back = ros_glue::fromReconfigure(DetectorConfig(), r);
  for (const DetectorTunable& t : detectorTunables()) {
    if (t.reconfigure) {
      EXPECT_EQ(t.get(back), t.get(c)) << t.name();
    } else {
      EXPECT_EQ(t.get(back), t.get(DetectorConfig())) << t.name() << " is not reconfigurable but was changed";
    }
  }
}
