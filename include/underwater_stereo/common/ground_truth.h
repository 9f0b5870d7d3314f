// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Exact truth about one object of a rendered stereo pair: plain data that the simulator fills and a
/// StereoFrame (camera tier) carries, so it lives here and neither tier includes the other.

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include <string>

namespace underwater_stereo {
namespace sim {

/// The scene's world frame (the left optical frame at time 0: x right, y down, z forward) in a REP-103 fixed
/// frame with the same origin (x forward, y left, z up), which the simulated head publishes as odom.
inline Eigen::Isometry3d fixedFromWorld() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return t;
}

struct GroundTruthObject {
  std::string name;
  std::string shape;                     ///< "sphere", "cylinder", "box" or "plane"
  std::string colour;                    ///< designated colour class
  Eigen::Vector3d albedo;                ///< linear RGB 0..1
  Eigen::Vector3d size_m;                ///< [m] as DetectedObject.size
  Eigen::Vector3d centre_world_m;        ///< [m] world frame (left optical frame at time 0)
  Eigen::Vector3d centre_left_m;         ///< [m] left optical frame at this frame's time
  Eigen::Quaterniond orientation_left;   ///< object frame in the left optical frame
  double range_m = 0.0;                  ///< [m] |centre_left_m|
  int visible_pixels = 0;                ///< left-image pixels that see the object
  cv::Rect roi_left;                     ///< [px] bounding box of those pixels (empty when not visible)
};

}  // namespace sim
}  // namespace underwater_stereo
