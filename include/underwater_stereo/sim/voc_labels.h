// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Training labels from the simulator's exact truth: Pascal VOC XML boxes and a per-pixel label image.

#include <opencv2/core.hpp>

#include <string>
#include <vector>

#include "underwater_stereo/common/ground_truth.h"

namespace underwater_stereo {
namespace sim {

/// Objects of a rendered pair that get a label: those whose colour is in `labelled_colours` and whose pixels span at
/// least two columns and two rows, in ground-truth order. Others (distractors) are background. (A sliver one pixel
/// wide has VOC corners xmin == xmax, which readers that take xmax as exclusive, learn_colours among them, refuse
/// as an empty box.)
std::vector<std::size_t> labelledObjects(const std::vector<GroundTruthObject>& truth,
                                         const std::vector<std::string>& labelled_colours);

/// Pascal VOC XML for the left image `filename` of `size`: one <object> per entry of `labelled` (indices into
/// `truth`), in that order, with <name> = its colour, <bndbox> 1-based inclusive pixel corners as VOC has them,
/// <truncated> 1 when its pixels touch the image border, <difficult> 1 when it shows fewer than
/// `min_pixels` pixels, and <segmented>1</segmented> (the mask holds the exact pixels).
/// @throw std::invalid_argument when an index is out of range or an object shows no pixel.
std::string vocAnnotation(const std::string& filename, const cv::Size& size, const std::vector<GroundTruthObject>& truth,
                          const std::vector<std::size_t>& labelled, int min_pixels);

/// CV_8UC1 label image: k (1-based) where the left image sees the k-th entry of `labelled`, 0 elsewhere.
/// `left_labels` is RenderedPair::left_labels (1 + object index). @throw std::invalid_argument when it is not
/// CV_16UC1 or more than 255 objects are labelled.
cv::Mat labelMask(const cv::Mat& left_labels, const std::vector<std::size_t>& labelled);

}  // namespace sim
}  // namespace underwater_stereo
