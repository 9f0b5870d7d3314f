// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/tracking/target_matcher.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {

TargetMatcher::TargetMatcher(const TrackingConfig& config) : config_(config) {
  const auto problems = config_.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid tracking configuration", problems));
}

TargetMatch TargetMatcher::match(const std::string& colour, ShapeKind shape, const Eigen::Vector3d& size_m) const {
  TargetMatch out;
  const double size = size_m.allFinite() ? size_m.maxCoeff() : std::numeric_limits<double>::quiet_NaN();
  double best_error = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < config_.targets.size(); ++i) {
    const Target& t = config_.targets[i];
    if (t.colour != colour || !shapesAgree(t.shape, shape)) continue;
    out.fit = TargetFit::kWrongSize;  // its colour and shape: from here on only the size can make it fit
    const double error = std::abs(size - t.size_m) / t.size_m;
    if (error <= t.size_tolerance && error < best_error) {
      best_error = error;
      out.target = static_cast<int>(i);
    }
  }
  if (out.target >= 0) out.fit = TargetFit::kTarget;
  return out;
}

bool TargetMatcher::keep(const TargetMatch& m) const {
  switch (m.fit) {
    case TargetFit::kTarget:
      return true;
    case TargetFit::kNoTarget:
      return !config_.targets_only;
    case TargetFit::kWrongSize:
      return !config_.reject_wrong_size && !config_.targets_only;
  }
  return false;
}

}  // namespace underwater_stereo
