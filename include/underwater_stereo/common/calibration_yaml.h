// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Reading a camera calibration from the YAML that ROS's camera_calibration writes, checking every
/// field's shape and value before anything is built from it.

#include <yaml-cpp/yaml.h>

#include <string>

#include "underwater_stereo/common/stereo_calibration.h"

namespace underwater_stereo {

/// A calibration from a parsed camera_calibration YAML document: image_width, image_height,
/// camera_matrix (3x3), projection_matrix (3x4), and optionally camera_name, distortion_model
/// (plumb_bob or rational_polynomial; default plumb_bob), distortion_coefficients (1xN; default none),
/// rectification_matrix (3x3; default identity). Matrices are maps {rows, cols, data}.
/// @throw std::invalid_argument listing every problem: a missing or unknown key, a matrix whose rows/cols
/// or data length is wrong, a value that is not a number, and everything CameraCalibration::validate() finds.
CameraCalibration parseCameraCalibration(const YAML::Node& root);

/// parseCameraCalibration() of the file at `path`. @throw std::invalid_argument naming the file.
CameraCalibration loadCameraCalibrationFile(const std::string& path);

}  // namespace underwater_stereo
