// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/dbscan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace underwater_stereo {

std::vector<std::string> ClusterConfig::validate() const {
  std::vector<std::string> p;
  if (!(eps_m > 0.0 && eps_m <= 1.0)) p.push_back("cluster.eps_m must be in (0, 1]");
  if (min_points < 1 || min_points > 10000) p.push_back("cluster.min_points must be in [1, 10000]");
  return p;
}

namespace {

/// The cube of side `size` that `p` lies in, as one number ordered as (x, y, z) (21 bits each, offset to
/// be non-negative): cubes stacked along z are consecutive numbers.
std::int64_t cubeKey(const Eigen::Vector3f& p, float size) {
  constexpr std::int64_t kOffset = 1 << 20;
  const auto axis = [&](float v) { return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(v / size)) + kOffset, 0, 2 * kOffset - 1); };
  return (axis(p.x()) << 42) | (axis(p.y()) << 21) | axis(p.z());
}

/// (cube of side `size`, index) of every finite point, sorted: points of a cube together, cubes in key order.
std::vector<std::pair<std::int64_t, int>> sortedByCube(const std::vector<Eigen::Vector3f>& points, float size) {
  std::vector<std::pair<std::int64_t, int>> keyed;
  keyed.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (points[i].allFinite()) keyed.emplace_back(cubeKey(points[i], size), static_cast<int>(i));
  }
  std::sort(keyed.begin(), keyed.end());
  return keyed;
}

/// Points merged into cubic cells, in the order of their first point: cell i holds the points
/// members[first[i]] .. members[first[i + 1] - 1] (ascending), whose mean is centroid[i].
struct Cells {
  std::vector<int> members, first;
  std::vector<Eigen::Vector3f> centroid;

  std::size_t size() const { return centroid.size(); }
  int weight(int i) const { return first[i + 1] - first[i]; }
};

/// Sorting (cell, point) pairs instead of a hash map of growing lists: no allocation per cell.
Cells voxelize(const std::vector<Eigen::Vector3f>& points, float cell) {
  const std::vector<std::pair<std::int64_t, int>> keyed = sortedByCube(points, cell);
  std::vector<std::pair<int, int>> runs;  // (first point, start in keyed) per cell
  for (std::size_t k = 0; k < keyed.size(); ++k) {
    if (k == 0 || keyed[k].first != keyed[k - 1].first) runs.emplace_back(keyed[k].second, static_cast<int>(k));
  }
  std::sort(runs.begin(), runs.end());
  Cells cells;
  cells.members.reserve(keyed.size());
  cells.first.reserve(runs.size() + 1);
  cells.centroid.reserve(runs.size());
  for (const auto& [first_point, start] : runs) {
    cells.first.push_back(static_cast<int>(cells.members.size()));
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    for (std::size_t k = start; k < keyed.size() && keyed[k].first == keyed[start].first; ++k) {
      cells.members.push_back(keyed[k].second);
      sum += points[keyed[k].second];
    }
    cells.centroid.push_back(sum / static_cast<float>(cells.members.size() - cells.first.back()));
  }
  cells.first.push_back(static_cast<int>(cells.members.size()));
  return cells;
}

/// Fixed-radius neighbours of the cell centroids: the centroids sorted by the radius-wide cube they lie in,
/// so a query reads the 3 x 3 runs of cubes (each three stacked along z) around its own: everything within
/// the radius lies there. A few times faster than a kd-tree for the few hundred centroids of an object.
class RadiusGrid {
 public:
  RadiusGrid(const std::vector<Eigen::Vector3f>& centroids, float radius) : radius_(radius) {
    for (const auto& [key, index] : sortedByCube(centroids, radius)) {
      keys_.push_back(key);
      centroids_.push_back(centroids[index]);
      indices_.push_back(index);
    }
  }

  /// Indices of the centroids strictly closer than the radius to `p` (p's own included).
  void neighbours(const Eigen::Vector3f& p, std::vector<int>& out) const {
    out.clear();
    const std::int64_t centre = cubeKey(p, radius_);
    const float r2 = radius_ * radius_;
    for (const std::int64_t dx : {-1, 0, 1}) {
      for (const std::int64_t dy : {-1, 0, 1}) {
        const std::int64_t column = centre + (dx << 42) + (dy << 21);
        const auto first = std::lower_bound(keys_.begin(), keys_.end(), column - 1);
        for (auto k = static_cast<std::size_t>(first - keys_.begin()); k < keys_.size() && keys_[k] <= column + 1; ++k) {
          if ((centroids_[k] - p).squaredNorm() < r2) out.push_back(indices_[k]);
        }
      }
    }
  }

 private:
  float radius_;
  std::vector<std::int64_t> keys_;
  std::vector<Eigen::Vector3f> centroids_;
  std::vector<int> indices_;
};

}  // namespace

std::vector<std::vector<int>> dbscan(const std::vector<Eigen::Vector3f>& points, const ClusterConfig& config) {
  std::vector<std::vector<int>> clusters;
  if (points.empty()) return clusters;
  // DBSCAN over cells half of eps wide, each weighted by its points: on dense stereo surfaces every
  // point has hundreds of neighbours, cells a handful; the result differs from point-wise DBSCAN only by
  // the cell size.
  const Cells voxels = voxelize(points, static_cast<float>(config.eps_m / 2));
  if (voxels.size() == 0) return clusters;
  const RadiusGrid grid(voxels.centroid, static_cast<float>(config.eps_m));

  constexpr int kUnvisited = -2, kNoise = -1;
  std::vector<int> label(voxels.size(), kUnvisited);
  std::vector<int> neighbours, seeds;
  auto isCore = [&](int v) {
    grid.neighbours(voxels.centroid[v], neighbours);
    int weight = 0;
    for (const int n : neighbours) weight += voxels.weight(n);
    return weight >= config.min_points;
  };
  std::vector<std::vector<int>> voxel_clusters;
  for (std::size_t i = 0; i < voxels.size(); ++i) {
    if (label[i] != kUnvisited) continue;
    if (!isCore(static_cast<int>(i))) {
      label[i] = kNoise;
      continue;
    }
    const int id = static_cast<int>(voxel_clusters.size());
    voxel_clusters.emplace_back(1, static_cast<int>(i));
    label[i] = id;
    // Each cell joins (and is queued) once: labelled when first reached, expanded only if it is a core.
    auto absorb = [&](const std::vector<int>& around) {
      for (const int j : around) {
        if (label[j] == kNoise) {  // border cell: joins, is not expanded
          label[j] = id;
          voxel_clusters[id].push_back(j);
        } else if (label[j] == kUnvisited) {
          label[j] = id;
          voxel_clusters[id].push_back(j);
          seeds.push_back(j);
        }
      }
    };
    seeds.clear();
    absorb(neighbours);
    for (std::size_t k = 0; k < seeds.size(); ++k) {
      if (isCore(seeds[k])) absorb(neighbours);
    }
  }
  for (const auto& vc : voxel_clusters) {
    clusters.emplace_back();
    for (const int v : vc) {
      clusters.back().insert(clusters.back().end(), voxels.members.begin() + voxels.first[v], voxels.members.begin() + voxels.first[v + 1]);
    }
    std::sort(clusters.back().begin(), clusters.back().end());
  }
  std::sort(clusters.begin(), clusters.end(), [](const auto& a, const auto& b) { return a.size() > b.size(); });
  return clusters;
}

}  // namespace underwater_stereo
