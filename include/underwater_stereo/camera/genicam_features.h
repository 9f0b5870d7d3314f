// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Setting GenICam features by the first name a camera knows, and reading the value back.

#include <string>
#include <vector>

namespace underwater_stereo {

/// A camera's GenICam features (implemented over Aravis; a map in tests). Setters may throw
/// std::runtime_error when the camera refuses a value.
class FeatureAccess {
 public:
  virtual ~FeatureAccess() = default;
  virtual bool available(const std::string& name) const = 0;
  virtual void setFloat(const std::string& name, double value) = 0;
  virtual double getFloat(const std::string& name) const = 0;
  virtual void setInteger(const std::string& name, long value) = 0;
  virtual long getInteger(const std::string& name) const = 0;
  virtual void setString(const std::string& name, const std::string& value) = 0;  ///< also enumerations
  virtual std::string getString(const std::string& name) const = 0;
  virtual void setBoolean(const std::string& name, bool value) = 0;
  virtual bool getBoolean(const std::string& name) const = 0;
  virtual void execute(const std::string& name) = 0;  ///< a command, e.g. TriggerSoftware
};

/// The first of `names` the camera has. @throw std::runtime_error listing the names when it has none.
std::string firstAvailable(const FeatureAccess& camera, const std::vector<std::string>& names);

/// Sets a float feature by the first available of `names` (e.g. {"ExposureTime", "ExposureTimeAbs"}) and
/// returns the value read back. @throw std::runtime_error when no name is available, the camera refuses the
/// value, or it reads back more than `tolerance` (relative) away (a value clamped to the camera's range).
double setFloatFeature(FeatureAccess& camera, const std::vector<std::string>& names, double value,
                       double tolerance = 0.01);

/// Sets an enumeration or string feature and checks it reads back the same.
/// @throw std::runtime_error as setFloatFeature.
void setStringFeature(FeatureAccess& camera, const std::string& name, const std::string& value);

}  // namespace underwater_stereo
