// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Waiting in rostest nodes.
#include <ros/ros.h>

#include <functional>

namespace underwater_stereo {
namespace test {

/// Polls `done` every 50 ms for up to `seconds` of wall time; its last answer.
inline bool waitFor(const std::function<bool()>& done, double seconds) {
  const ros::WallTime end = ros::WallTime::now() + ros::WallDuration(seconds);
  while (ros::ok() && ros::WallTime::now() < end) {
    if (done()) return true;
    ros::WallDuration(0.05).sleep();
  }
  return done();
}

}  // namespace test
}  // namespace underwater_stereo
