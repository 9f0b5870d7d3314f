// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/dbscan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace underwater_stereo {

std::vector<std::string> ClusterConfig::validate() const {
  std::vector<std::string> p;
  if (!(eps_m >= 0.001 && eps_m <= 1.0)) p.push_back("cluster.eps_m must be in [0.001, 1]");
  if (min_points < 1 || min_points > 10000) p.push_back("cluster.min_points must be in [1, 10000]");
  if (!(eps_disparity_px >= 0.0 && eps_disparity_px <= 10.0)) p.push_back("cluster.eps_disparity_px must be in [0, 10]");
  return p;
}

double neighbourhoodRadius(const std::vector<Eigen::Vector3f>& points, const ClusterConfig& config,
                           double focal_baseline) {
  if (config.eps_disparity_px <= 0.0 || !(focal_baseline > 0.0)) return config.eps_m;
  std::vector<float> depth;
  depth.reserve(points.size());
  for (const Eigen::Vector3f& p : points) {
    if (p.allFinite()) depth.push_back(p.z());
  }
  if (depth.empty()) return config.eps_m;
  const auto middle = depth.begin() + static_cast<std::ptrdiff_t>(depth.size() / 2);
  std::nth_element(depth.begin(), middle, depth.end());
  const double z = *middle;
  return std::clamp(config.eps_disparity_px * z * z / focal_baseline, config.eps_m, std::max(config.eps_m, 1.0));
}

namespace {

/// The cube of side `size` that `p` lies in, as one number ordered as (x, y, z) (21 bits each, offset to
/// be non-negative): cubes stacked along z are consecutive numbers.
std::int64_t cubeKey(const Eigen::Vector3f& p, float size) {
  constexpr std::int64_t kOffset = 1 << 20;
  const auto axis = [&](float v) { return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(v / size)) + kOffset, 0, 2 * kOffset - 1); };
  return (axis(p.x()) << 42) | (axis(p.y()) << 21) | axis(p.z());
}

/// Non-negative 64-bit keys to small integers, by open addressing (linear probing): the few hundred cells
/// or columns of one object, where std::unordered_map's node per key costs more than the search it saves.
class KeyTable {
 public:
  explicit KeyTable(std::size_t capacity) {
    std::size_t size = 16;
    while (size < 2 * capacity) size *= 2;
    keys_.assign(size, kEmpty);
    values_.resize(size);
    mask_ = size - 1;
  }

  /// The value stored for `key`, storing `value` first if the key is new.
  int findOrInsert(std::int64_t key, int value) {
    std::size_t slot = hash(key);
    while (keys_[slot] != kEmpty && keys_[slot] != key) slot = (slot + 1) & mask_;
    if (keys_[slot] == kEmpty) {
      keys_[slot] = key;
      values_[slot] = value;
    }
    return values_[slot];
  }

  /// The value stored for `key`, or -1.
  int find(std::int64_t key) const {
    for (std::size_t slot = hash(key); keys_[slot] != kEmpty; slot = (slot + 1) & mask_) {
      if (keys_[slot] == key) return values_[slot];
    }
    return -1;
  }

 private:
  static constexpr std::int64_t kEmpty = -1;
  std::size_t hash(std::int64_t key) const {
    return static_cast<std::size_t>((static_cast<std::uint64_t>(key) * 0x9E3779B97F4A7C15ull) >> 32) & mask_;
  }
  std::vector<std::int64_t> keys_;
  std::vector<int> values_;
  std::size_t mask_ = 0;
};

/// Points merged into cubic cells, in the order of their first point: cell i holds the points
/// members[first[i]] .. members[first[i + 1] - 1] (ascending), whose mean is centroid[i].
struct Cells {
  std::vector<int> members, first;
  std::vector<Eigen::Vector3f> centroid;

  std::size_t size() const { return centroid.size(); }
  int weight(int i) const { return first[i + 1] - first[i]; }
};

/// Cells numbered as their first point is met (a table of cube keys), then the points laid out cell by cell
/// in ascending order (a counting sort): linear in the points, no allocation per cell.
Cells voxelize(const std::vector<Eigen::Vector3f>& points, float cell) {
  KeyTable table(points.size());
  std::vector<int> cell_of(points.size(), -1);
  int cells_found = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) continue;
    cell_of[i] = table.findOrInsert(cubeKey(points[i], cell), cells_found);
    if (cell_of[i] == cells_found) ++cells_found;
  }
  Cells cells;
  cells.first.assign(cells_found + 1, 0);
  for (const int c : cell_of) {
    if (c >= 0) ++cells.first[c + 1];
  }
  for (int c = 0; c < cells_found; ++c) cells.first[c + 1] += cells.first[c];
  cells.members.resize(cells.first.back());
  std::vector<int> next(cells.first.begin(), cells.first.end() - 1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (cell_of[i] >= 0) cells.members[next[cell_of[i]]++] = static_cast<int>(i);
  }
  cells.centroid.reserve(cells_found);
  for (int c = 0; c < cells_found; ++c) {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    for (int k = cells.first[c]; k < cells.first[c + 1]; ++k) sum += points[cells.members[k]];
    cells.centroid.push_back(sum / static_cast<float>(cells.weight(c)));
  }
  return cells;
}

/// Fixed-radius neighbours of the cell centroids: the centroids sorted by the radius-wide cube they lie in
/// (then by index), each column of cubes (x, y) found through a table, so a query reads the 3 x 3 columns
/// around its own and, in each, the three cubes stacked along z around it: everything within the radius lies
/// there. A few times faster than a kd-tree for the few hundred centroids of an object.
class RadiusGrid {
 public:
  RadiusGrid(const std::vector<Eigen::Vector3f>& centroids, float radius)
      : radius_(radius), columns_(centroids.size()) {
    std::vector<std::pair<std::int64_t, int>> keyed;
    keyed.reserve(centroids.size());
    for (std::size_t i = 0; i < centroids.size(); ++i) keyed.emplace_back(cubeKey(centroids[i], radius), static_cast<int>(i));
    std::sort(keyed.begin(), keyed.end());
    for (const auto& [key, index] : keyed) {
      columns_.findOrInsert(columnOf(key), static_cast<int>(keys_.size()));
      keys_.push_back(key);
      centroids_.push_back(centroids[index]);
      indices_.push_back(index);
    }
  }

  /// Indices of the centroids strictly closer than the radius to `p` (p's own included), column by column
  /// (x, then y, ascending), by cube and then index within a column.
  void neighbours(const Eigen::Vector3f& p, std::vector<int>& out) const {
    out.clear();
    const std::int64_t centre = cubeKey(p, radius_);
    const float r2 = radius_ * radius_;
    for (const std::int64_t dx : {-1, 0, 1}) {
      for (const std::int64_t dy : {-1, 0, 1}) {
        const std::int64_t column = centre + (dx << 42) + (dy << 21);
        const int start = columns_.find(columnOf(column));
        if (start < 0) continue;
        const std::int64_t base = columnOf(column);
        for (auto k = static_cast<std::size_t>(start); k < keys_.size() && columnOf(keys_[k]) == base && keys_[k] <= column + 1; ++k) {
          if (keys_[k] >= column - 1 && (centroids_[k] - p).squaredNorm() < r2) out.push_back(indices_[k]);
        }
      }
    }
  }

 private:
  /// The key of a cube with its z part cleared: the same for every cube of one column.
  static std::int64_t columnOf(std::int64_t key) { return key & ~((std::int64_t{1} << 21) - 1); }

  float radius_;
  KeyTable columns_;  // column -> first position in keys_
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
