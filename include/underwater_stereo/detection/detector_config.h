// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Configuration of the whole detection pipeline, as config/detector.yaml holds it.

#include <functional>
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
  /// [px] Learned source: a usable frame darker than quality.enhance_below is searched at this width instead
  /// (480 for the head's 1920x1200: a quarter, each searched pixel averaging 4x4 of the frame's, where sensor noise
  /// drowns the objects' contrast at 2x2; docs/accuracy.md, "Dark frames searched coarser"), never finer than
  /// search_scale and while the searched image keeps kMinSearchSidePx per side. 0: off.
  int dark_search_width_px = 480;
  /// Threads working on one pair: the calling one and up to pair_threads - 1 of the detector's own (1: the
  /// calling thread alone). The 2D search's passes and the pair's objects are shared out over them, with the
  /// same result whatever the number. Not OpenCV's pool, which the nodelet keeps single-threaded: a second core
  /// shortens a pair's latency by ~15-25 % for ~5 % more CPU (docs/performance.md, session 6).
  int pair_threads = 2;

  /// Every problem of every section.
  std::vector<std::string> validate() const;
};

/// One tunable number of the detector configuration: the single place its YAML name, field, accepted range and
/// meaning are written. parseDetectorConfig reads these fields by it, DetectorConfig::validate refuses values
/// outside its range, and the dynamic_reconfigure mapping (ros_glue) and its tests use it, so the .cfg, the
/// YAML and the README cannot drift apart unnoticed.
struct DetectorTunable {
  const char* section;      ///< YAML section ("" at the top level)
  const char* key;          ///< YAML key in that section
  double min, max;          ///< accepted values, both ends included (the component's own validate() agrees; the
                            ///< colour_model rows are checked whatever candidates.source, their component's only
                            ///< for the learnt source)
  const char* reconfigure;  ///< its name in cfg/DetectorTuning.cfg; nullptr when not tunable at run time
  const char* doc;          ///< one line: what it does, with its unit
  double* (*real)(DetectorConfig&);  ///< the field when it is a double (else nullptr)
  int* (*integer)(DetectorConfig&);  ///< the field when it is an int (else nullptr)

  /// "section.key" (or "key" at the top level).
  std::string name() const;
  double get(const DetectorConfig& c) const;
  /// Sets the field (an int field takes the value rounded).
  void set(DetectorConfig& c, double value) const;
};

/// Every tunable number, section by section (the colour lists, the mask section, colour_model.levels and the
/// non-numeric keys are read by hand).
const std::vector<DetectorTunable>& detectorTunables();

/// Parses the detector configuration (keys as in config/detector.yaml; missing keys keep their defaults).
/// A relative colour_model.file is found in `base_dir` (the config file's folder; empty: the working folder).
/// @throw std::invalid_argument listing every problem (unknown keys, wrong types, invalid values, a colour
/// model that cannot be read or lacks a designated colour).
DetectorConfig parseDetectorConfig(const YAML::Node& root, const std::string& base_dir = "");
/// `edit`, when given, changes a copy of the file's YAML before it is parsed (a tool's override, e.g. a key left
/// out); relative files are still found in the file's folder.
/// @throw std::invalid_argument when the file cannot be read or is invalid.
DetectorConfig loadDetectorConfigFile(const std::string& path, const std::function<void(YAML::Node&)>& edit = {});

/// The colour and candidate settings for a frame scaled by `scale` (config.search_scale, or a dark frame's
/// scale): kernels, blur and areas scaled with it (blur kept odd).
DetectorConfig scaledForSearch(const DetectorConfig& config, double scale);

}  // namespace underwater_stereo
