// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/genicam_features.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace underwater_stereo {

std::string firstAvailable(const FeatureAccess& camera, const std::vector<std::string>& names) {
  for (const std::string& n : names) {
    if (camera.available(n)) return n;
  }
  std::ostringstream m;
  m << "the camera has none of the features";
  for (const std::string& n : names) m << " " << n;
  throw std::runtime_error(m.str());
}

double setFloatFeature(FeatureAccess& camera, const std::vector<std::string>& names, double value, double tolerance) {
  const std::string name = firstAvailable(camera, names);
  try {
    camera.setFloat(name, value);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("the camera refused " + name + " = " + std::to_string(value) + ": " + e.what());
  }
  const double read = camera.getFloat(name);
  if (std::abs(read - value) > tolerance * std::max(std::abs(value), 1e-9)) {
    throw std::runtime_error("the camera refused " + name + " = " + std::to_string(value) + " (it reads " +
                             std::to_string(read) + ")");
  }
  return read;
}

void setStringFeature(FeatureAccess& camera, const std::string& name, const std::string& value) {
  if (!camera.available(name)) throw std::runtime_error("the camera has no feature " + name);
  try {
    camera.setString(name, value);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("the camera refused " + name + " = " + value + ": " + e.what());
  }
  const std::string read = camera.getString(name);
  if (read != value) throw std::runtime_error("the camera refused " + name + " = " + value + " (it reads " + read + ")");
}

}  // namespace underwater_stereo
