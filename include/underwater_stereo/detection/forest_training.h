// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file How the learnt models' random forests (OpenCV's cv::ml::RTrees) are trained: one set of options and one
/// training call for the colour model and the shape model; and how every learnt model's file is opened.

#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include <string>
#include <vector>

namespace underwater_stereo {

struct ForestTraining {
  int trees = 100;
  int max_depth = 10;
  /// Rarer classes are weighted up by (a reference class's count / their count)^balance (0: not at all).
  double balance = 0.6;
  int seed = 1;  ///< OpenCV's random generator is seeded with it: the same data gives the same forest

  std::vector<std::string> validate() const;
};

/// A forest trained on `samples` (CV_32F, one row per sample) with class `responses` (CV_32S, one per row) and
/// per-class `priors` (CV_32F, one per class), with `options`' trees, depth and seed.
cv::Ptr<cv::ml::RTrees> trainForest(const cv::Mat& samples, const cv::Mat& responses, const cv::Mat& priors,
                                    const ForestTraining& options);

/// The model file at `path` opened for reading. @throw std::invalid_argument beginning with `named` when it cannot be.
cv::FileStorage openModelFile(const std::string& path, const std::string& named);

/// The model file at `path` opened for writing; a ".gz" file is gzipped at level 9 (OpenCV's default is 3; the
/// committed check stays under 2 MiB that way). @throw std::runtime_error beginning with `named` when it cannot be.
cv::FileStorage createModelFile(const std::string& path, const std::string& named);

}  // namespace underwater_stereo
