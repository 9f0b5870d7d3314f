// SPDX-License-Identifier: BSD-3-Clause
// evaluate_detector: renders simulated scenes, runs the detector on every pair and compares the detections
// with the ground truth. Prints a Markdown table per scene and overall (recall, false detections per frame,
// range/position/size errors, shape accuracy).
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "underwater_stereo/detection/detector.h"
#include "tool_helpers.h"
#include "underwater_stereo/sim/renderer.h"

namespace {

using namespace underwater_stereo;

const char* kUsage =
    "usage: evaluate_detector --config detector.yaml [--frames N] [--rate HZ] [--verbose] SCENE.yaml...\n"
    "  Renders frames 0..N-1 of each scene (default 10 at 2 Hz), detects, and compares with ground truth.\n"
    "  Objects count when 0.5-5 m away with >= 400 visible pixels and a designated colour.\n";

struct Stats {
  int frames = 0, eligible = 0, found = 0, false_detections = 0, shape_eligible = 0, shape_correct = 0;
  std::vector<double> range_err, position_err, size_err_near;  // relative
  std::vector<double> ms;
};

double sizeError(const sim::GroundTruthObject& gt, const Detection& d) {
  auto rel = [](double a, double b) { return std::abs(a - b) / b; };
  if (gt.shape == "sphere") return rel(d.size_m.x(), gt.size_m.x());
  if (gt.shape == "cylinder") return std::max(rel(d.size_m.x(), gt.size_m.x()), rel(d.size_m.z(), gt.size_m.z()));
  std::vector<double> a{d.size_m.x(), d.size_m.y(), d.size_m.z()}, b{gt.size_m.x(), gt.size_m.y(), gt.size_m.z()};
  std::sort(a.rbegin(), a.rend());
  std::sort(b.rbegin(), b.rend());
  double worst = 0;
  for (int i = 0; i < 3; ++i) {
    if (b[i] > 0) worst = std::max(worst, rel(a[i], b[i]));
  }
  return worst;
}

bool verbose = false;

void accumulate(Stats& s, const std::vector<sim::GroundTruthObject>& truth, const DetectionResult& r,
                const std::vector<std::string>& designated) {
  ++s.frames;
  s.ms.push_back(r.timings.total_ms);
  std::vector<bool> used(r.objects.size(), false);
  for (const auto& gt : truth) {
    const bool is_designated = std::find(designated.begin(), designated.end(), gt.colour) != designated.end();
    const bool eligible = is_designated && gt.visible_pixels >= 400 && gt.range_m >= 0.5 && gt.range_m <= 5.0;
    // The detection of this object: same colour, its ROI centre inside the object's ROI.
    int match = -1;
    for (std::size_t i = 0; i < r.objects.size(); ++i) {
      const cv::Rect& roi = r.objects[i].roi;
      const cv::Point centre(roi.x + roi.width / 2, roi.y + roi.height / 2);
      if (!used[i] && r.objects[i].colour == gt.colour && gt.roi_left.contains(centre)) {
        match = static_cast<int>(i);
        break;
      }
    }
    if (match >= 0) used[match] = true;
    if (verbose) {
      std::cerr << "  truth " << gt.name << " " << gt.shape << " size " << gt.size_m.transpose() << " at "
                << gt.centre_left_m.transpose() << " (" << gt.visible_pixels << " px)";
      if (match >= 0) {
        const Detection& d = r.objects[match];
        std::cerr << "\n    found " << d.colour << " " << d.shape << "/" << d.outline << " size " << d.size_m.transpose()
                  << " at " << d.position_m.transpose() << " rmse " << d.fit_rmse_m << " points " << d.points.size();
      }
      std::cerr << "\n";
    }
    if (!eligible) continue;
    ++s.eligible;
    if (match < 0) continue;
    ++s.found;
    const Detection& d = r.objects[match];
    s.range_err.push_back(std::abs(d.range_m - gt.range_m) / gt.range_m);
    s.position_err.push_back((d.position_m - gt.centre_left_m).norm() / gt.range_m);
    if (gt.range_m <= 3.0) s.size_err_near.push_back(sizeError(gt, d));
    if (gt.visible_pixels >= 1500) {
      ++s.shape_eligible;
      s.shape_correct += d.shape == gt.shape;
    }
  }
  for (std::size_t i = 0; i < used.size(); ++i) {
    s.false_detections += !used[i];
    if (verbose && !used[i]) {
      std::cerr << "  FALSE " << r.objects[i].colour << " " << r.objects[i].shape << " at "
                << r.objects[i].position_m.transpose() << " roi " << r.objects[i].roi << "\n";
    }
  }
}

void printRow(const std::string& name, const Stats& s) {
  std::cout << "| " << name << " | " << s.frames << " | " << s.eligible << " | " << std::fixed << std::setprecision(1)
            << (s.eligible ? 100.0 * s.found / s.eligible : NAN) << " | " << std::setprecision(2)
            << (s.frames ? double(s.false_detections) / s.frames : NAN) << " | " << std::setprecision(2)
            << 100 * tools::percentile(s.range_err, 0.5) << " | " << 100 * tools::percentile(s.range_err, 0.95) << " | "
            << 100 * tools::percentile(s.position_err, 0.95) << " | " << 100 * tools::percentile(s.size_err_near, 0.5) << " | "
            << std::setprecision(1) << (s.shape_eligible ? 100.0 * s.shape_correct / s.shape_eligible : NAN) << " | "
            << tools::percentile(s.ms, 0.5) << " |\n";
}

void merge(Stats& into, const Stats& s) {
  into.frames += s.frames;
  into.eligible += s.eligible;
  into.found += s.found;
  into.false_detections += s.false_detections;
  into.shape_eligible += s.shape_eligible;
  into.shape_correct += s.shape_correct;
  auto append = [](std::vector<double>& to, const std::vector<double>& from) { to.insert(to.end(), from.begin(), from.end()); };
  append(into.range_err, s.range_err);
  append(into.position_err, s.position_err);
  append(into.size_err_near, s.size_err_near);
  append(into.ms, s.ms);
}

}  // namespace

int main(int argc, char** argv) {
  std::string config_path;
  int frames = 10;
  double rate = 2.0;
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--verbose") {
      verbose = true;
    } else if ((a == "--config" || a == "--frames" || a == "--rate") && i + 1 < argc) {
      const std::string v = argv[++i];
      if (a == "--config") config_path = v;
      else if (a == "--frames") frames = std::atoi(v.c_str());
      else rate = std::atof(v.c_str());
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << kUsage;
      return 2;
    } else {
      scenes.push_back(a);
    }
  }
  if (config_path.empty() || scenes.empty() || frames < 1 || !(rate > 0)) {
    std::cerr << kUsage;
    return 2;
  }
  try {
    const DetectorConfig config = loadDetectorConfigFile(config_path);
    std::vector<std::string> designated;
    for (const auto& c : config.colours.classes) designated.push_back(c.name);
    Stats all;
    std::cout << "| scene | frames | objects | recall % | false/frame | range err median % | range err p95 % |"
                 " position err p95 % | size err median % (<= 3 m) | shape correct % | detector ms (median) |\n"
                 "|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& path : scenes) {
      const sim::Renderer renderer(sim::loadSceneFile(path));
      Detector detector(config, renderer.calibration());
      Stats s;
      for (int k = 0; k < frames; ++k) {
        const sim::RenderedPair pair = renderer.render(k / rate, static_cast<std::uint64_t>(k));
        accumulate(s, pair.ground_truth,
                   detector.detect(RawFrame(pair.left, pixelLayoutOf(pair.encoding)), RawFrame(pair.right, pixelLayoutOf(pair.encoding))),
                   designated);
      }
      std::string name = path.substr(path.find_last_of('/') + 1);
      printRow(name, s);
      merge(all, s);
    }
    printRow("**all**", all);
  } catch (const std::exception& e) {
    std::cerr << "evaluate_detector: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
