// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file One object seen as several 2D regions (a near object split by a highlight or a shading band): which
/// detections are pieces of one object, the one region they make together, and the region they were cut from.

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

/// The region that the candidates `group` (indices into `whole_of`) stood in place of as its pieces, when they are
/// exactly the candidates that stood in its place (`whole_of`: each candidate's region, -1 for none; as
/// FrontEnd::whole_of); else -1. @throw std::invalid_argument when an index of `group` lies outside `whole_of`.
int regionOfPieces(const std::vector<int>& group, const std::vector<int>& whole_of);

/// The share of `region`'s pixels (full-resolution masks, soft edges: pixels from 128 on count) that `pieces` (their
/// union, joinedCandidate) cover; 0 where the region has none.
double shareCovered(const Candidate& pieces, const Candidate& region);

}  // namespace underwater_stereo
