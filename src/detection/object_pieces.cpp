// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/object_pieces.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace underwater_stereo {
namespace {

struct Box {
  Eigen::Vector3f min, max;
};

Box boxOf(const std::vector<Eigen::Vector3f>& points) {
  Box b{Eigen::Vector3f::Constant(1e30f), Eigen::Vector3f::Constant(-1e30f)};
  for (const auto& p : points) {
    b.min = b.min.cwiseMin(p);
    b.max = b.max.cwiseMax(p);
  }
  return b;
}

/// Cell of `p` in a grid of cubes `size` wide, packed into one key (21 bits per axis, offset to stay positive).
std::uint64_t cellKey(const Eigen::Vector3f& p, float size, int dx = 0, int dy = 0, int dz = 0) {
  const auto axis = [size](float v, int d) {
    return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / size)) + d + (1 << 20)) & 0x1FFFFF;
  };
  return axis(p.x(), dx) << 42 | axis(p.y(), dy) << 21 | axis(p.z(), dz);
}

/// Whether any point of `a` lies within `gap` of one of `b` (boxes first: most pairs are far apart; then b's
/// points in cubes `gap` wide, so each point of a is compared with b's points in the 27 cubes around it only:
/// linear in the points, whatever stereo.max_points allows).
bool touching(const std::vector<Eigen::Vector3f>& a, const Box& box_a, const std::vector<Eigen::Vector3f>& b,
              const Box& box_b, float gap) {
  if (a.empty() || b.empty()) return false;
  if (((box_a.min.array() - gap) > box_b.max.array()).any() || ((box_b.min.array() - gap) > box_a.max.array()).any()) {
    return false;
  }
  std::unordered_map<std::uint64_t, std::vector<int>> cells;
  for (int j = 0; j < static_cast<int>(b.size()); ++j) {
    if (b[j].allFinite()) cells[cellKey(b[j], gap)].push_back(j);
  }
  const float gap2 = gap * gap;
  for (const auto& p : a) {
    if (!p.allFinite()) continue;
    if (((p.array() + gap) < box_b.min.array()).any() || ((p.array() - gap) > box_b.max.array()).any()) continue;
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find(cellKey(p, gap, dx, dy, dz));
          if (it == cells.end()) continue;
          for (int j : it->second) {
            if ((p - b[j]).squaredNorm() <= gap2) return true;
          }
        }
      }
    }
  }
  return false;
}

int root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

std::vector<std::vector<int>> piecesOfOneObject(const std::function<bool(int, int)>& may_join,
                                                const std::vector<std::vector<Eigen::Vector3f>>& clusters, double gap_m) {
  if (!(gap_m > 0)) throw std::invalid_argument("piecesOfOneObject: gap_m must be > 0");
  const int n = static_cast<int>(clusters.size());
  std::vector<Box> boxes;
  for (const auto& c : clusters) boxes.push_back(boxOf(c));
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (int i = 0; i < n; ++i) {
    for (int j = i + 1; j < n; ++j) {
      if (root(parent, i) == root(parent, j) || !may_join(i, j)) continue;
      if (touching(clusters[i], boxes[i], clusters[j], boxes[j], static_cast<float>(gap_m))) {
        parent[root(parent, j)] = root(parent, i);
      }
    }
  }
  std::vector<std::vector<int>> groups(n);
  for (int i = 0; i < n; ++i) groups[root(parent, i)].push_back(i);
  std::vector<std::vector<int>> out;
  for (auto& g : groups) {
    if (g.size() > 1) out.push_back(std::move(g));
  }
  std::sort(out.begin(), out.end());
  return out;
}

Candidate joinedCandidate(const std::vector<const Candidate*>& pieces, const cv::Size& frame) {
  if (pieces.empty()) throw std::invalid_argument("joinedCandidate: no pieces");
  cv::Rect roi = pieces.front()->roi;
  const Candidate* best = pieces.front();
  const Candidate* largest_piece = pieces.front();
  cv::Scalar colour_sum;
  double area = 0;
  for (const Candidate* p : pieces) {
    if (p->colour_index != best->colour_index) throw std::invalid_argument("joinedCandidate: pieces of different colours");
    roi |= p->roi;
    if (p->colour_fraction > best->colour_fraction) best = p;
    if (p->area_px > largest_piece->area_px) largest_piece = p;
    colour_sum += p->mean_bgr * p->area_px;
    area += p->area_px;
  }
  roi &= cv::Rect(cv::Point(), frame);
  Candidate c = *best;
  c.roi = roi;
  c.mask = cv::Mat(roi.size(), CV_8UC1, cv::Scalar(0));  // a new buffer: assigning zeros() would clear the piece's mask
  for (const Candidate* p : pieces) {
    const cv::Rect r = p->roi & roi;
    if (r.empty()) continue;
    cv::Mat into = c.mask(r - roi.tl());
    cv::bitwise_or(into, p->mask(r - p->roi.tl()), into);
  }
  std::vector<cv::Point> outline = largestOutline(c.mask, roi.tl());
  if (!outline.empty()) c.contour = std::move(outline);
  c.area_px = area;
  if (c.contour.size() >= 3) c.outline = classifyOutline(c.contour);
  if (area > 0) c.mean_bgr = colour_sum * (1.0 / area);
  c.face_contrast = largest_piece->face_contrast;
  return c;
}

int regionOfPieces(const std::vector<int>& group, const std::vector<int>& whole_of) {
  const int n = static_cast<int>(whole_of.size());
  for (int k : group) {
    if (k < 0 || k >= n) throw std::invalid_argument("regionOfPieces: a candidate index outside whole_of");
  }
  if (group.empty()) return -1;
  const int region = whole_of[group.front()];
  if (region < 0) return -1;
  for (int k = 0; k < n; ++k) {
    const bool in_group = std::find(group.begin(), group.end(), k) != group.end();
    if ((whole_of[k] == region) != in_group) return -1;
  }
  return region;
}

double shareCovered(const Candidate& pieces, const Candidate& region) {
  cv::Mat in_region;
  cv::compare(region.mask, 128, in_region, cv::CMP_GE);
  const int all = cv::countNonZero(in_region);
  if (all == 0) return 0.0;
  const cv::Rect both = pieces.roi & region.roi;
  if (both.empty()) return 0.0;
  cv::Mat in_pieces;
  cv::compare(pieces.mask(both - pieces.roi.tl()), 128, in_pieces, cv::CMP_GE);
  cv::bitwise_and(in_pieces, in_region(both - region.roi.tl()), in_pieces);
  return static_cast<double>(cv::countNonZero(in_pieces)) / all;
}

}  // namespace underwater_stereo
