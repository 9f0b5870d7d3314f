// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file The detector's dynamic_reconfigure parameters (cfg/DetectorTuning.cfg) <-> DetectorConfig, by the
/// names in detectorTunables(): the table is the one place a tunable's field and range are written.

#include <string>
#include <vector>

#include "underwater_stereo/DetectorTuningConfig.h"
#include "underwater_stereo/detection/detector_config.h"

namespace underwater_stereo {
namespace ros_glue {

/// The values of `c` into the reconfigurable parameters of `r`.
void toReconfigure(const DetectorConfig& c, DetectorTuningConfig& r);

/// `c` with the reconfigurable parameters of `r` (not validated).
DetectorConfig fromReconfigure(DetectorConfig c, const DetectorTuningConfig& r);

/// Every disagreement between cfg/DetectorTuning.cfg and detectorTunables(): a .cfg parameter without a table
/// row, a row naming a parameter the .cfg lacks, a range or type that differs. Empty when they agree.
std::vector<std::string> reconfigureTableProblems();

}  // namespace ros_glue
}  // namespace underwater_stereo
