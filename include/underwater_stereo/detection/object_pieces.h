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

/// Groups of indices into `clusters` (one per detection: its 3D cluster) whose clusters come within `gap_m` of
/// each other, directly or through other members, among detections `may_join(i, j)` allows to be pieces of one
/// object (i < j; e.g. those of one colour): the pieces DBSCAN would have joined had they been matched as one
/// region (`gap_m` its eps). Only groups of two or more are returned, each in increasing index order.
std::vector<std::vector<int>> piecesOfOneObject(const std::function<bool(int, int)>& may_join,
                                                const std::vector<std::vector<Eigen::Vector3f>>& clusters, double gap_m);

/// The region `pieces` make together (all of one colour, full-resolution masks, inside `frame`): their masks
/// joined, the outer contour of that union (the largest part where it is not connected) and its outline, their
/// summed area and area-weighted mean colour; the face contrast of the largest piece; the colour confidence and
/// learned saliency cut of the most confident one. @throw std::invalid_argument when `pieces` is empty or mixes
/// colours.
Candidate joinedCandidate(const std::vector<const Candidate*>& pieces, const cv::Size& frame);

}  // namespace underwater_stereo
