// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Simulator ground truth -> underwater_stereo/GroundTruth.

#include <std_msgs/Header.h>
#include <underwater_stereo/GroundTruth.h>

#include <vector>

#include "underwater_stereo/sim/ground_truth.h"

namespace underwater_stereo {
namespace ros_glue {

GroundTruth toGroundTruthMsg(const std::vector<sim::GroundTruthObject>& objects, const std_msgs::Header& header);

}  // namespace ros_glue
}  // namespace underwater_stereo
