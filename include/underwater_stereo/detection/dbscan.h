// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file DBSCAN clustering of 3D points (cells eps/2 wide, neighbours from a grid eps wide).

#include <Eigen/Core>

#include <string>
#include <vector>

namespace underwater_stereo {

struct ClusterConfig {
  double eps_m = 0.04;  ///< [m] neighbourhood radius
  int min_points = 8;   ///< neighbours (the point included) that make a core point

  std::vector<std::string> validate() const;
};

/// Clusters of `points` as index lists, largest first; points in no cluster (noise) and non-finite points
/// are left out. DBSCAN runs over cubic cells eps/2 wide weighted by their points (a cell is core when the
/// cells within eps hold min_points points), which on dense stereo surfaces is far cheaper than point-wise.
std::vector<std::vector<int>> dbscan(const std::vector<Eigen::Vector3f>& points, const ClusterConfig& config);

}  // namespace underwater_stereo
