// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/camera/camera_controls.h"

#include <cmath>
#include <stdexcept>

namespace underwater_stereo {

double setExposureUs(FeatureAccess& camera, double exposure_us) {
  if (camera.available("ExposureAuto") && camera.getString("ExposureAuto") != "Off") {
    setStringFeature(camera, "ExposureAuto", "Off");
  }
  return setFloatFeature(camera, {"ExposureTime", "ExposureTimeAbs"}, exposure_us);
}

double exposureUs(const FeatureAccess& camera) {
  return camera.getFloat(firstAvailable(camera, {"ExposureTime", "ExposureTimeAbs"}));
}

bool gainInDb(const FeatureAccess& camera) { return camera.available("Gain") || camera.available("GainAbs"); }

double setGain(FeatureAccess& camera, double value) {
  if (camera.available("GainAuto") && camera.getString("GainAuto") != "Off") setStringFeature(camera, "GainAuto", "Off");
  if (gainInDb(camera)) return setFloatFeature(camera, {"Gain", "GainAbs"}, value, 0.02);
  const long raw = std::lround(value);
  camera.setInteger(firstAvailable(camera, {"GainRaw"}), raw);
  const long read = camera.getInteger("GainRaw");
  if (read != raw) {
    throw std::runtime_error("the camera refused GainRaw = " + std::to_string(raw) + " (it reads " +
                             std::to_string(read) + ")");
  }
  return static_cast<double>(read);
}

double gain(const FeatureAccess& camera) {
  if (gainInDb(camera)) return camera.getFloat(firstAvailable(camera, {"Gain", "GainAbs"}));
  return static_cast<double>(camera.getInteger(firstAvailable(camera, {"GainRaw"})));
}

std::string enablePtp(FeatureAccess& camera) {
  for (const std::string name : {"PtpEnable", "GevIEEE1588"}) {
    if (!camera.available(name)) continue;
    camera.setBoolean(name, true);
    if (!camera.getBoolean(name)) throw std::runtime_error("the camera refused " + name + " = true");
    return name;
  }
  return "";
}

std::string ptpStatus(FeatureAccess& camera) {
  // Cameras that latch their PTP data set show the state only after the latch command.
  for (const auto& [latch, status] : {std::make_pair("PtpDataSetLatch", "PtpStatus"),
                                      std::make_pair("GevIEEE1588DataSetLatch", "GevIEEE1588StatusLatched")}) {
    if (camera.available(latch) && camera.available(status)) {
      camera.execute(latch);
      return camera.getString(status);
    }
  }
  for (const std::string status : {"PtpStatus", "GevIEEE1588Status"}) {
    if (camera.available(status)) return camera.getString(status);
  }
  return "";
}

bool ptpSettled(const std::string& status) { return status == "Master" || status == "Slave"; }

}  // namespace underwater_stereo
