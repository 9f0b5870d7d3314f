// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file DBSCAN clustering of 3D points (cells eps/2 wide, neighbours from a grid eps wide).

#include <Eigen/Core>

#include <string>
#include <vector>

namespace underwater_stereo {

struct ClusterConfig {
  double eps_m = 0.04;  ///< [m] neighbourhood radius, the smallest: wider for far objects (eps_disparity_px)
  int min_points = 8;   ///< neighbours (the point included) that make a core point
  /// The radius is at least the depth this many pixels of disparity span at the points' median depth (z^2 / (f B)
  /// per pixel): a far object's points spread along their rays with stereo's depth noise (5 cm at 4.7 m with the
  /// 224 px m of the sampled rig) and fall apart under eps_m alone (docs/accuracy.md, "The cluster radius follows
  /// stereo's depth step"). 0: eps_m alone.
  double eps_disparity_px = 0.5;

  std::vector<std::string> validate() const;
};

/// The neighbourhood radius [m] for `points` seen by a rig of focal length x baseline `focal_baseline` [px m]:
/// config.eps_m, or where it is wider the depth config.eps_disparity_px of disparity spans at the points' median
/// depth (finite points only; eps_m when there are none), never above 1 m (eps_m's own limit).
double neighbourhoodRadius(const std::vector<Eigen::Vector3f>& points, const ClusterConfig& config,
                           double focal_baseline);

/// Clusters of `points` within config.eps_m (callers set it to neighbourhoodRadius for a rig's points) as index lists,
/// largest first; points in no cluster (noise) and non-finite points
/// are left out. DBSCAN runs over cubic cells eps/2 wide weighted by their points (a cell is core when the
/// cells within eps hold min_points points), which on dense stereo surfaces is far cheaper than point-wise.
std::vector<std::vector<int>> dbscan(const std::vector<Eigen::Vector3f>& points, const ClusterConfig& config);

}  // namespace underwater_stereo
