// SPDX-License-Identifier: BSD-3-Clause
// Time the tracker takes per stereo pair with N confirmed tracks in view (their detections with noise), on a
// moving camera: prints median and p99 microseconds per update.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "underwater_stereo/tracking/tracker.h"
#include "tool_helpers.h"

using namespace underwater_stereo;

int main(int argc, char** argv) {
  int objects = 10, frames = 3000;
  const char* usage = "usage: benchmark_tracker [--objects N (10, at most 15)] [--frames N (3000)]\n";
  try {
    for (int i = 1; i < argc; i += 2) {
      const std::string arg = argv[i];
      if (arg == "--help" || arg == "-h") {
        std::fputs(usage, stdout);
        return 0;
      }
      if (arg != "--objects" && arg != "--frames") throw std::invalid_argument("unknown option " + arg);
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      // At most 15: the objects stand on a grid of 5 x 3 places in view (more would stand behind them, hidden).
      if (arg == "--objects") objects = static_cast<int>(tools::wholeNumberIn(argv[i + 1], 1, 15, arg));
      else frames = static_cast<int>(tools::wholeNumberIn(argv[i + 1], 10, 10000000, arg));
    }
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "benchmark_tracker: %s\n%s", e.what(), usage);
    return 2;
  }
  const char* colours[] = {"red", "orange", "yellow", "green"};
  TrackingConfig config;
  Tracker tracker(config);
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::vector<Eigen::Vector3d> truth;
  // Rows of five, 0.6 m apart at 3 m: every object clear of the others in the image (none hidden or merged).
  for (int i = 0; i < objects; ++i) truth.emplace_back(-1.2 + 0.6 * (i % 5), -0.6 + 0.6 * (i / 5), 3.0);
  std::vector<double> us;
  for (int k = 0; k < frames; ++k) {
    TrackingFrame f;
    f.stamp_s = k / 15.0;
    f.camera_pose.translation() = Eigen::Vector3d(0.01 * f.stamp_s, 0, 0);
    f.in_view = [](const Eigen::Vector3d& p) { return p.z() > 0.5 && p.z() < 5.0; };
    for (int i = 0; i < objects; ++i) {
      Observation o;
      o.colour = colours[i % 4];
      o.shape = ShapeKind::kSphere;
      o.size_m = Eigen::Vector3d::Constant(0.25);
      o.position_m = f.camera_pose.inverse() * truth[static_cast<std::size_t>(i)] +
                     Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
      f.observations.push_back(o);
    }
    const auto start = std::chrono::steady_clock::now();
    tracker.update(f);
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(us.begin(), us.end());
  std::printf("tracks=%zu objects=%d frames=%d median_us=%.1f p99_us=%.1f max_us=%.1f\n", tracker.tracks().size(),
              objects, frames, us[us.size() / 2], us[us.size() * 99 / 100], us.back());
  return 0;
}
