// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file One JSON object per detection (the DetectedObject field names), for command-line tools.

#include <string>

#include "underwater_stereo/detection/detector.h"

namespace underwater_stereo {

/// {"status": "OK", "mean_brightness": .., "dark_fraction": .., "bright_fraction": .., "enhanced": ..}
std::string qualityJson(const QualityReport& quality);

/// One line: {"file": .., "id": .., "colour": .., "measured_colour": [r, g, b] (0-1), "outline": ..,
/// "roi": [x, y, width, height], "confidence": .., "cut_by_border": true/false, "quality": {..}} and, when `with_3d`, also "shape",
/// "size": [x, y, z], "range", "position": [x, y, z], "orientation": [x, y, z, w], "num_points", "fit_rmse".
/// Strings are escaped; non-finite numbers are written as null.
std::string detectionJson(const std::string& file, int id, const Detection& d, const QualityReport& quality,
                          bool with_3d);

/// One line for a frame without detections: {"file": .., "id": null, "quality": {..}}.
std::string emptyFrameJson(const std::string& file, const QualityReport& quality);

/// One line for a region looked at and not reported: {"file": .., "rejected": {"colour": .., "roi": [x, y,
/// width, height], "confidence": .., "reason": ..}}.
std::string rejectionJson(const std::string& file, const Rejection& rejection);

}  // namespace underwater_stereo
