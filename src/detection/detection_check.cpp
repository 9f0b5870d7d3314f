// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/detection_check.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "underwater_stereo/detection/blob_proposals.h"

namespace underwater_stereo {
namespace {

/// Sizes under a millimetre are taken as one (the logarithm stays finite).
constexpr double kLeastSizeM = 1e-3;

}  // namespace

std::vector<std::string> checkFeatureNames(const std::vector<std::string>& colours) {
  std::vector<std::string> names = blobFeatureNames();
  names.push_back("share_background");
  for (const std::string& c : colours) names.push_back("share_" + c);
  for (const char* n : {"range_m", "log_largest_size", "log_smallest_size", "shape", "cut_by_border",
                        "fit_rmse_of_range", "matched_share"}) {
    names.emplace_back(n);
  }
  return names;
}

std::vector<float> checkFeatures(const std::vector<float>& colour_features, const MeasuredForCheck& m) {
  if (colour_features.empty()) throw std::invalid_argument("checkFeatures: the candidate has no colour model's features");
  std::vector<float> f = colour_features;
  for (double v : {m.range_m, std::log(std::max(m.largest_size_m, kLeastSizeM)),
                   std::log(std::max(m.smallest_size_m, kLeastSizeM)), double(m.shape), double(m.cut_by_border),
                   m.fit_rmse_m / std::max(m.range_m, 0.1), m.matched_share}) {
    f.push_back(static_cast<float>(v));
  }
  return f;
}

}  // namespace underwater_stereo
