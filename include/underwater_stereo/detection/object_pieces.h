// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file One object seen as several 2D regions (a near object split by a highlight or a shading band): which
/// detections are pieces of one object, and the one region they make together.

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <functional>
#include <vector>

#include "underwater_stereo/detection/candidate_finder.h"

namespace underwater_stereo {

/// Detections of another colour than each other may still be pieces of one object (a yellow ball's shaded half
/// read orange) when their boxes overlap at least this share of the smaller one (colour_model.max_overlap's default).
constexpr double kPieceBoxOverlap = 0.3;

/// Whether two measured candidates may be pieces of one object (their 3D clusters then decide): of one colour,
/// or with boxes overlapping at least kPieceBoxOverlap of the smaller.
bool mayBePiecesOfOneObject(const Candidate& a, const Candidate& b);

/// Groups of indices into `clusters` (one 3D cluster per detection) whose clusters come within `gap_m` of each
/// other, directly or through other members, among detections that `may_join(i, j)` (i < j) allows to be pieces of
/// one object: the pieces DBSCAN would have joined had they been matched as one region (`gap_m` its eps). Only
/// groups of two or more are returned, each in increasing index order.
std::vector<std::vector<int>> piecesOfOneObject(const std::vector<std::vector<Eigen::Vector3f>>& clusters, double gap_m,
                                                const std::function<bool(int, int)>& may_join);

/// The region `pieces` make together (full-resolution masks, inside `frame`): their masks
/// joined, the outer contour of that union (the largest part where it is not connected) and its outline, their
/// summed area and area-weighted mean colour; the face contrast of the largest piece; the colour, colour
/// confidence and learned saliency cut of the most confident one. @throw std::invalid_argument when `pieces` is
/// empty.
Candidate joinedCandidate(const std::vector<const Candidate*>& pieces, const cv::Size& frame);

}  // namespace underwater_stereo
