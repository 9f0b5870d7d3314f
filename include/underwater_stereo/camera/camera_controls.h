// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Exposure, gain and IEEE 1588 (PTP) on a GenICam camera, whichever generation of feature names it has.

#include <string>

#include "underwater_stereo/camera/genicam_features.h"

namespace underwater_stereo {

/// Switches ExposureAuto off (where the camera has it), sets ExposureTime or ExposureTimeAbs [us] and returns the
/// value read back. @throw std::runtime_error when the camera refuses or clamps it (the message names the value).
double setExposureUs(FeatureAccess& camera, double exposure_us);
double exposureUs(const FeatureAccess& camera);

/// True when the gain is in dB (Gain or GainAbs); false when the camera has GainRaw only (its own units).
bool gainInDb(const FeatureAccess& camera);
/// Switches GainAuto off (where present), sets the gain (dB, or GainRaw rounded) and returns it read back.
/// @throw std::runtime_error as setExposureUs.
double setGain(FeatureAccess& camera, double gain);
double gain(const FeatureAccess& camera);

/// Enables IEEE 1588 through PtpEnable (SFNC 2.x) or GevIEEE1588 (older GigE cameras). Returns the feature
/// used, or "" when the camera has neither (then nothing is changed). @throw std::runtime_error when it refuses.
std::string enablePtp(FeatureAccess& camera);
/// The camera's PTP port state (Initializing, Listening, Master, Slave, ...; latched first where the camera
/// needs it), or "" without PTP.
std::string ptpStatus(FeatureAccess& camera);
/// Master or Slave: the clock takes part in a settled PTP domain.
bool ptpSettled(const std::string& status);

}  // namespace underwater_stereo
