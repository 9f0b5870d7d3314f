// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <random>

#include "underwater_stereo/detection/dbscan.h"

using namespace underwater_stereo;

TEST(Dbscan, SeparatesBlobsAndDropsNoise) {
  const unsigned seed = 42;
  std::mt19937 rng(seed);
  std::normal_distribution<float> blob(0.0F, 0.01F);
  std::uniform_real_distribution<float> spread(-2.0F, 2.0F);
  std::vector<Eigen::Vector3f> pts;
  for (int i = 0; i < 300; ++i) pts.emplace_back(blob(rng), blob(rng), 2.0F + blob(rng));         // big blob
  for (int i = 0; i < 120; ++i) pts.emplace_back(0.5F + blob(rng), blob(rng), 2.0F + blob(rng));  // small blob
  for (int i = 0; i < 20; ++i) pts.emplace_back(spread(rng), spread(rng), 6.0F + spread(rng));    // sparse noise
  const auto clusters = dbscan(pts, ClusterConfig{0.03, 8});
  ASSERT_EQ(clusters.size(), 2U) << "seed " << seed;
  EXPECT_EQ(clusters[0].size(), 300U);
  EXPECT_EQ(clusters[1].size(), 120U);
  for (int i : clusters[0]) EXPECT_LT(i, 300);
  for (int i : clusters[1]) {
    EXPECT_GE(i, 300);
    EXPECT_LT(i, 420);
  }
}

TEST(Dbscan, EmptyInputGivesNoCluster) { EXPECT_TRUE(dbscan({}, ClusterConfig{}).empty()); }

TEST(Dbscan, InvalidConfigIsReported) {
  EXPECT_TRUE(ClusterConfig{}.validate().empty());
  EXPECT_EQ((ClusterConfig{0.0, 0}.validate().size()), 2U);
}
