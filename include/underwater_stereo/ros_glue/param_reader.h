// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Reading typed parameters from the parameter server, collecting every problem.

#include <ros/node_handle.h>

#include <string>
#include <vector>

namespace underwater_stereo {
namespace ros_glue {

/// Reads private parameters into config fields; a parameter of the wrong type is a problem, a missing one
/// keeps the field's default.
class ParamReader {
 public:
  ParamReader(const ros::NodeHandle& nh, std::vector<std::string>& problems) : nh_(nh), problems_(problems) {}

  template <typename T>
  void optional(const std::string& name, T& value) {
    if (!nh_.hasParam(name)) return;
    T read{};
    if (nh_.getParam(name, read)) {
      value = read;
    } else {
      problems_.push_back(nh_.resolveName(name) + ": has the wrong type");
    }
  }

  template <typename T>
  void required(const std::string& name, T& value) {
    if (!nh_.hasParam(name)) {
      problems_.push_back(nh_.resolveName(name) + ": missing");
      return;
    }
    optional(name, value);
  }

 private:
  const ros::NodeHandle& nh_;
  std::vector<std::string>& problems_;
};

}  // namespace ros_glue
}  // namespace underwater_stereo
