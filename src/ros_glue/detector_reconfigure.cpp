// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/ros_glue/detector_reconfigure.h"

#include <dynamic_reconfigure/config_tools.h>

#include <boost/any.hpp>

#include <algorithm>
#include <cmath>

namespace underwater_stereo {
namespace ros_glue {
namespace {

const DetectorTunable* tunableNamed(const std::string& reconfigure_name) {
  for (const DetectorTunable& t : detectorTunables()) {
    if (t.reconfigure && reconfigure_name == t.reconfigure) return &t;
  }
  return nullptr;
}

/// A .cfg parameter's value in `r` as a number (its type is double or int).
double valueOf(const DetectorTuningConfig::AbstractParamDescription& d, const DetectorTuningConfig& r) {
  boost::any value;
  d.getValue(r, value);
  return d.type == "int" ? boost::any_cast<int>(value) : boost::any_cast<double>(value);
}

}  // namespace

void toReconfigure(const DetectorConfig& c, DetectorTuningConfig& r) {
  dynamic_reconfigure::Config msg;
  r.__toMessage__(msg);
  for (auto& p : msg.doubles) {
    if (const DetectorTunable* t = tunableNamed(p.name)) p.value = t->get(c);
  }
  for (auto& p : msg.ints) {
    if (const DetectorTunable* t = tunableNamed(p.name)) p.value = static_cast<int>(std::lround(t->get(c)));
  }
  r.__fromMessage__(msg);
}

DetectorConfig fromReconfigure(DetectorConfig c, const DetectorTuningConfig& r) {
  for (const auto& d : DetectorTuningConfig::__getParamDescriptions__()) {
    if (const DetectorTunable* t = tunableNamed(d->name)) t->set(c, valueOf(*d, r));
  }
  return c;
}

std::vector<std::string> reconfigureTableProblems() {
  std::vector<std::string> p;
  const DetectorTuningConfig& min = DetectorTuningConfig::__getMin__();
  const DetectorTuningConfig& max = DetectorTuningConfig::__getMax__();
  std::vector<std::string> in_cfg;
  for (const auto& d : DetectorTuningConfig::__getParamDescriptions__()) {
    in_cfg.push_back(d->name);
    const DetectorTunable* t = tunableNamed(d->name);
    if (!t) {
      p.push_back("cfg/DetectorTuning.cfg: " + d->name + " has no row in detectorTunables()");
      continue;
    }
    if (d->description != t->doc) {
      p.push_back(t->name() + ": described as '" + d->description + "' in the .cfg, '" + t->doc + "' in the table");
    }
    if ((d->type == "int") != (t->integer != nullptr)) {
      p.push_back(t->name() + ": " + d->type + " in the .cfg, " + (t->integer ? "int" : "double") + " in the table");
    }
    if (valueOf(*d, min) != t->min || valueOf(*d, max) != t->max) {
      p.push_back(t->name() + ": range [" + std::to_string(valueOf(*d, min)) + ", " + std::to_string(valueOf(*d, max)) +
                  "] in cfg/DetectorTuning.cfg (" + d->name + "), [" + std::to_string(t->min) + ", " +
                  std::to_string(t->max) + "] in detectorTunables()");
    }
  }
  for (const DetectorTunable& t : detectorTunables()) {
    if (t.reconfigure && std::find(in_cfg.begin(), in_cfg.end(), t.reconfigure) == in_cfg.end()) {
      p.push_back(t.name() + ": reconfigurable as " + t.reconfigure + " in detectorTunables() but not in the .cfg");
    }
  }
  return p;
}

}  // namespace ros_glue
}  // namespace underwater_stereo
