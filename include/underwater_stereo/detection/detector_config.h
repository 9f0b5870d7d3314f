// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Configuration of the whole detection pipeline, as config/detector.yaml holds it.

#include <string>
#include <vector>

#include "underwater_stereo/detection/candidate_finder.h"
#include "underwater_stereo/detection/colour_segmenter.h"
#include "underwater_stereo/detection/dbscan.h"
#include "underwater_stereo/detection/image_quality.h"
#include "underwater_stereo/detection/learned_candidates.h"
#include "underwater_stereo/detection/roi_stereo_matcher.h"
#include "underwater_stereo/detection/shape_fitter.h"

namespace YAML {
class Node;
}

namespace underwater_stereo {

struct DetectorConfig {
  QualityConfig quality;
  ColourMaskConfig colours;
  CandidateConfig candidates;
  LearnedColourConfig learned;  ///< the `colour_model` section; used when candidates.source is learned
  StereoMatchConfig stereo;
  ClusterConfig cluster;
  ShapeFitConfig shape;
  int min_cluster_points = 30;  ///< an object needs at least this many 3D points in its main cluster
  /// The 2D stages (quality, colours, contours) run on the frame scaled by this (0.5: a quarter of the
  /// pixels, 4x faster); regions come back at full resolution with soft edges, and stereo runs at full
  /// resolution. Pixel sizes in the configuration (areas, kernels, blur) are full-resolution values.
  double search_scale = 0.5;

  /// Every problem of every section.
  std::vector<std::string> validate() const;
};

/// Parses the detector configuration (keys as in config/detector.yaml; missing keys keep their defaults).
/// A relative colour_model.file is found in `base_dir` (the config file's folder; empty: the working folder).
/// @throw std::invalid_argument listing every problem (unknown keys, wrong types, invalid values, a colour
/// model that cannot be read or lacks a designated colour).
DetectorConfig parseDetectorConfig(const YAML::Node& root, const std::string& base_dir = "");
/// @throw std::invalid_argument when the file cannot be read or is invalid.
DetectorConfig loadDetectorConfigFile(const std::string& path);

/// The colour and candidate settings for a frame scaled by config.search_scale: kernels, blur and areas
/// scaled with it (blur kept odd).
DetectorConfig scaledForSearch(const DetectorConfig& config);

}  // namespace underwater_stereo
