// SPDX-License-Identifier: BSD-3-Clause
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

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

/// Point-wise DBSCAN by brute force: each point's cluster id (-1: noise) and whether it is a core point.
std::pair<std::vector<int>, std::vector<bool>> bruteForceDbscan(const std::vector<Eigen::Vector3f>& pts, float eps,
                                                                int min_points) {
  const int n = static_cast<int>(pts.size());
  std::vector<std::vector<int>> near(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      if ((pts[i] - pts[j]).norm() < eps) near[i].push_back(j);
    }
  }
  std::vector<bool> core(n);
  for (int i = 0; i < n; ++i) core[i] = static_cast<int>(near[i].size()) >= min_points;
  std::vector<int> id(n, -1);
  int next = 0;
  for (int i = 0; i < n; ++i) {
    if (!core[i] || id[i] >= 0) continue;
    std::vector<int> stack{i};
    id[i] = next;
    while (!stack.empty()) {
      const int k = stack.back();
      stack.pop_back();
      for (int j : near[k]) {
        if (id[j] >= 0) continue;
        id[j] = next;
        if (core[j]) stack.push_back(j);
      }
    }
    ++next;
  }
  return {id, core};
}

// Points on a lattice 0.6 eps apart lie in cells (eps/2) of their own, so the cell-wise DBSCAN must agree
// with point-wise DBSCAN: the same points clustered, and core points together exactly when they are there
// (border points may go to either neighbouring cluster).
TEST(Dbscan, AgreesWithBruteForceWhereEveryPointHasItsOwnCell) {
  const float eps = 0.05F;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    std::bernoulli_distribution occupied(0.3 + 0.03 * seed);
    std::vector<Eigen::Vector3f> pts;
    for (int x = -6; x < 6; ++x) {
      for (int y = -6; y < 6; ++y) {
        for (int z = 20; z < 28; ++z) {
          if (occupied(rng)) pts.emplace_back(Eigen::Vector3f(x + 0.5F, y + 0.5F, z + 0.5F) * 0.6F * eps);
        }
      }
    }
    const int min_points = 3 + static_cast<int>(seed % 5);
    const auto [expected, core] = bruteForceDbscan(pts, eps, min_points);
    std::vector<int> got(pts.size(), -1);
    const auto clusters = dbscan(pts, ClusterConfig{eps, min_points});
    for (std::size_t c = 0; c < clusters.size(); ++c) {
      for (int i : clusters[c]) got[i] = static_cast<int>(c);
    }
    for (std::size_t i = 0; i < pts.size(); ++i) {
      ASSERT_EQ(got[i] >= 0, expected[i] >= 0) << "seed " << seed << " point " << i;
      if (!core[i]) continue;
      for (std::size_t j = 0; j < i; ++j) {
        if (!core[j]) continue;
        ASSERT_EQ(got[i] == got[j], expected[i] == expected[j]) << "seed " << seed << " points " << i << ", " << j;
      }
    }
  }
}

TEST(Dbscan, EmptyInputGivesNoCluster) { EXPECT_TRUE(dbscan({}, ClusterConfig{}).empty()); }

TEST(Dbscan, InvalidConfigIsReported) {
  EXPECT_TRUE(ClusterConfig{}.validate().empty());
  EXPECT_EQ((ClusterConfig{0.0, 0}.validate().size()), 2U);
  EXPECT_EQ((ClusterConfig{0.04, 8, -1.0}.validate().size()), 1U);
}

// A far object's stereo points: a 0.5 m panel at 4.7 m seen by a rig of 224 px m, each point's depth off by a
// disparity error of sigma 0.5 px (z^2 / fB per pixel: 10 cm), 800 points matched.
TEST(Dbscan, AFarObjectsPointsStayOneClusterWithTheRadiusOfItsDepthStep) {
  constexpr double kFocalBaseline = 224.0, kDepth = 4.7;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> across(-0.25F, 0.25F);
  std::normal_distribution<double> disparity_error(0.0, 0.5);
  std::vector<Eigen::Vector3f> points;
  for (int i = 0; i < 800; ++i) {
    const double d = kFocalBaseline / kDepth + disparity_error(rng);
    points.emplace_back(across(rng), across(rng), static_cast<float>(kFocalBaseline / d));
  }
  const ClusterConfig fixed{0.04, 8, 0.0}, following{0.04, 8, 0.5};
  EXPECT_DOUBLE_EQ(neighbourhoodRadius(points, fixed, kFocalBaseline), 0.04);
  const double radius = neighbourhoodRadius(points, following, kFocalBaseline);
  EXPECT_NEAR(radius, 0.5 * kDepth * kDepth / kFocalBaseline, 0.002);  // 4.9 cm
  ClusterConfig at_radius = following;
  at_radius.eps_m = radius;
  const auto apart = dbscan(points, fixed), together = dbscan(points, at_radius);
  ASSERT_FALSE(together.empty());
  EXPECT_GT(together.front().size(), 600U) << "the object's points are one cluster";
  EXPECT_LT(apart.empty() ? 0U : apart.front().size(), together.front().size() / 2) << "eps_m alone splits them";
  // Near, the depth step is finer than eps_m: the radius stays eps_m.
  for (Eigen::Vector3f& p : points) p.z() = 1.0F;
  EXPECT_DOUBLE_EQ(neighbourhoodRadius(points, following, kFocalBaseline), 0.04);
  EXPECT_DOUBLE_EQ(neighbourhoodRadius({}, following, kFocalBaseline), 0.04);
}
