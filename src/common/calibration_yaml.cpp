// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/common/calibration_yaml.h"

#include <stdexcept>
#include <vector>

#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {
namespace {

/// The `rows` x `cols` matrix `root[key]` ({rows, cols, data}) into `values` (row-major); false (and the
/// problems recorded) when absent or malformed.
bool readMatrix(const YAML::Node& root, const std::string& key, int rows, int cols, bool required,
                YamlFields& f, std::vector<double>& values) {
  const YAML::Node m = root[key];
  if (!m) {
    if (required) f.fail(key + ": missing");
    return false;
  }
  if (!m.IsMap()) {
    f.fail(key + ": expected a map {rows, cols, data}, got '" + YAML::Dump(m) + "'");
    return false;
  }
  f.onlyKeys(m, key + ".", {"rows", "cols", "data"});
  int r = -1, c = -1;
  std::vector<double> data;
  f.required(m, "rows", key + ".", r);
  f.required(m, "cols", key + ".", c);
  f.required(m, "data", key + ".", data);
  bool ok = true;
  if (r != rows) {
    f.fail(key + ".rows: must be " + std::to_string(rows) + ", is " + (r < 0 ? "missing or not a count" : std::to_string(r)));
    ok = false;
  }
  if (cols >= 0 && c != cols) {
    f.fail(key + ".cols: must be " + std::to_string(cols) + ", is " + (c < 0 ? "missing or not a count" : std::to_string(c)));
    ok = false;
  }
  if (c >= 0 && r >= 0 && data.size() != static_cast<std::size_t>(r) * static_cast<std::size_t>(c)) {
    f.fail(key + ".data: has " + std::to_string(data.size()) + " numbers, rows x cols = " + std::to_string(r) + "x" +
           std::to_string(c) + " needs " + std::to_string(static_cast<long long>(r) * c));
    ok = false;
  }
  if (ok) values = data;
  return ok;
}

}  // namespace

CameraCalibration parseCameraCalibration(const YAML::Node& root) {
  std::vector<std::string> problems;
  YamlFields f(problems);
  f.onlyKeys(root, "", {"image_width", "image_height", "camera_name", "camera_matrix", "distortion_model",
                        "distortion_coefficients", "rectification_matrix", "projection_matrix"});
  if (!root.IsMap()) throw std::invalid_argument(joinProblems("invalid camera calibration", problems));
  CameraCalibration c;
  f.required(root, "image_width", "", c.width);
  f.required(root, "image_height", "", c.height);
  std::string model = distortionModelName(c.distortion_model);
  f.optional(root, "distortion_model", "", model);
  if (const auto known = distortionModelOf(model)) {
    c.distortion_model = *known;
  } else {
    f.fail("distortion_model: '" + model + "' is not supported (plumb_bob or rational_polynomial)");
  }
  std::vector<double> values;
  if (readMatrix(root, "camera_matrix", 3, 3, true, f, values)) std::copy(values.begin(), values.end(), c.K.val);
  if (readMatrix(root, "rectification_matrix", 3, 3, false, f, values)) std::copy(values.begin(), values.end(), c.R.val);
  if (readMatrix(root, "projection_matrix", 3, 4, true, f, values)) std::copy(values.begin(), values.end(), c.P.val);
  if (readMatrix(root, "distortion_coefficients", 1, -1, false, f, values)) c.D = values;
  // Value problems only of a calibration read whole (a misread matrix would repeat as "K has no focal length").
  if (problems.empty()) problems = c.validate("calibration");
  if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid camera calibration", problems));
  return c;
}

CameraCalibration loadCameraCalibrationFile(const std::string& path) {
  return parseYamlFile(path, "camera calibration", parseCameraCalibration);
}

}  // namespace underwater_stereo
