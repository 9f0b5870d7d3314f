// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/dbscan.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <algorithm>

namespace underwater_stereo {

std::vector<std::string> ClusterConfig::validate() const {
  std::vector<std::string> p;
  if (!(eps_m > 0.0 && eps_m <= 1.0)) p.push_back("cluster.eps_m must be in (0, 1]");
  if (min_points < 1 || min_points > 10000) p.push_back("cluster.min_points must be in [1, 10000]");
  return p;
}

std::vector<std::vector<int>> dbscan(const std::vector<Eigen::Vector3f>& points, const ClusterConfig& config) {
  std::vector<std::vector<int>> clusters;
  if (points.empty()) return clusters;
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->reserve(points.size());
  for (const auto& p : points) cloud->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);

  constexpr int kUnvisited = -2, kNoise = -1;
  std::vector<int> label(points.size(), kUnvisited);
  std::vector<int> neighbours, seeds;
  std::vector<float> distances;
  const auto radius = static_cast<float>(config.eps_m);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (label[i] != kUnvisited) continue;
    if (tree.radiusSearch(cloud->points[i], radius, neighbours, distances) < config.min_points) {
      label[i] = kNoise;
      continue;
    }
    const int id = static_cast<int>(clusters.size());
    clusters.emplace_back();
    label[i] = id;
    clusters.back().push_back(static_cast<int>(i));
    seeds = neighbours;
    for (std::size_t k = 0; k < seeds.size(); ++k) {
      const int j = seeds[k];
      if (label[j] == kNoise) {  // border point
        label[j] = id;
        clusters.back().push_back(j);
      }
      if (label[j] != kUnvisited) continue;
      label[j] = id;
      clusters.back().push_back(j);
      if (tree.radiusSearch(cloud->points[j], radius, neighbours, distances) >= config.min_points) {
        seeds.insert(seeds.end(), neighbours.begin(), neighbours.end());
      }
    }
  }
  std::sort(clusters.begin(), clusters.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return clusters;
}

}  // namespace underwater_stereo
