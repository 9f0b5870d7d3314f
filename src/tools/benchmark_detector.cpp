// SPDX-License-Identifier: BSD-3-Clause
// benchmark_detector: per-stage and end-to-end timing of the Detector on rendered stereo pairs.
// Renders the pairs first (not timed), warms up once over them, then times `repeat` passes.
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "underwater_stereo/detection/detector.h"
#include "scene_files.h"
#include "tool_helpers.h"
#include "underwater_stereo/sim/renderer.h"

namespace {

using namespace underwater_stereo;

const char* kUsage =
    "usage: benchmark_detector --config detector.yaml [--frames N] [--rate HZ] [--repeat R] [--csv FILE]\n"
    "                          [--summary] [--pace HZ] [--opencv-threads N] SCENE.yaml...\n"
    "  Times the detector on frames 0..N-1 (default 10 at 2 Hz scene time) of each scene, R passes (default 5)\n"
    "  after one warm-up pass. Prints a Markdown table per scene (median per stage, end to end median and p99,\n"
    "  pairs/s); --csv writes one row per timed pair (scene, frame, objects, mean range, stage times);\n"
    "  --summary ends with one line over all pairs: median_ms=.. p99_ms=.. pairs_per_s=..\n"
    "  --pace HZ then runs 3 s of pairs per scene at HZ (as a camera delivers them) and prints the process's CPU\n"
    "  time per pair and in cores (thread pools that spin between pairs count); --opencv-threads N sets\n"
    "  cv::setNumThreads(N) (1: OpenCV single-threaded).\n";

/// CPU time [s] this process has used (all threads, user + system).
double processCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_utime.tv_sec + usage.ru_stime.tv_sec + 1e-6 * (usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

struct Pair {
  RawFrame left, right;  ///< as the camera sends them (Bayer): the detector's timing includes any conversion
};

}  // namespace

int main(int argc, char** argv) {
  std::string config_path, csv_path;
  int frames = 10, repeat = 5;
  double rate = 2.0;
  bool summary = false;
  double pace_hz = 0;
  std::vector<std::string> scenes;
  tools::OptionsGiven given;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) == 0) {
      try {
        given.add(a);
      } catch (const std::invalid_argument& e) {
        std::cerr << "benchmark_detector: " << e.what() << "\n" << kUsage;
        return 2;
      }
    }
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::cerr << "benchmark_detector: " << a << " needs a value\n" << kUsage;
        std::exit(2);
      }
      return argv[++i];
    };
    // A number option's value: the whole of it a number (a whole one where `whole`), else exit 2 naming it.
    auto number = [&](bool whole, double lo, double hi) {
      const std::string text = value();
      try {
        return whole ? static_cast<double>(tools::wholeNumberIn(text, static_cast<long long>(lo), static_cast<long long>(hi), a))
                     : tools::numberIn(text, lo, hi, a);
      } catch (const std::invalid_argument& e) {
        std::cerr << "benchmark_detector: " << e.what() << "\n" << kUsage;
        std::exit(2);
      }
    };
    if (a == "--config") config_path = value();
    else if (a == "--frames") frames = static_cast<int>(number(true, 1, 1e6));
    else if (a == "--rate") rate = number(false, 1e-3, 1e3);
    else if (a == "--repeat") repeat = static_cast<int>(number(true, 1, 1e4));
    else if (a == "--csv") csv_path = value();
    else if (a == "--summary") summary = true;
    else if (a == "--pace") pace_hz = number(false, 0, 1e3);
    else if (a == "--opencv-threads") cv::setNumThreads(static_cast<int>(number(true, 0, 256)));
    else if (a == "--help" || a == "-h") {
      std::cout << kUsage;
      return 0;
    } else {
      scenes.push_back(a);
    }
  }
  if (config_path.empty() || scenes.empty() || frames < 1 || repeat < 1 || !(rate > 0) || pace_hz < 0) {
    std::cerr << kUsage;
    return 2;
  }
  // The configuration and every scene (and the detector on its rig) read before anything is timed: a bad one is
  // named at once (exit 2), not after the scenes before it.
  DetectorConfig config;
  std::vector<std::pair<std::string, sim::Scene>> scene_files;
  {
    std::vector<std::string> problems;
    bool config_loaded = false;
    try {
      config = loadDetectorConfigFile(config_path);
      config_loaded = true;
    } catch (const std::exception& e) {
      problems.push_back(e.what());
    }
    scene_files = tools::readSceneFiles(scenes, config_loaded ? &config : nullptr, frames, rate, problems);
    if (!problems.empty()) {
      for (const std::string& p : problems) std::cerr << "benchmark_detector: " << p << "\n";
      return 2;
    }
  }
  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    if (!csv.is_open()) {
      std::cerr << "benchmark_detector: --csv " << csv_path << ": cannot be written\n";
      return 2;
    }
    csv << "scene,frame,objects,mean_range_m,quality_ms,colour_ms,contours_ms,rectify_ms,matching_ms,reprojection_ms,"
           "cluster_ms,fit_ms,total_ms\n";
  }
  std::cout << "OpenCV threads: " << cv::getNumThreads() << ", CPUs: " << cv::getNumberOfCPUs() << "\n\n";
  std::cout << "| scene | pairs timed | objects per pair | quality | colour | contours | ROI rectify | matching | "
               "reprojection | cluster | fit | end to end median ms | p99 ms | pairs/s |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::vector<double> all_totals;
  std::vector<std::string> paced;
  try {
    for (const auto& [path, scene] : scene_files) {
      const sim::Renderer renderer(scene);
      std::vector<Pair> pairs;
      for (int k = 0; k < frames; ++k) {
        const sim::RenderedPair r = renderer.render(k / rate, k);
        pairs.push_back({RawFrame(r.left, pixelLayoutOf(r.encoding)), RawFrame(r.right, pixelLayoutOf(r.encoding))});
      }
      Detector detector(config, renderer.calibration());
      for (const Pair& p : pairs) detector.detect(p.left, p.right);  // warm-up: maps, allocations
      constexpr int kStages = 8;  // and the total last
      std::vector<double> stage[kStages + 1];
      double objects = 0;
      for (int pass = 0; pass < repeat; ++pass) {
        for (int k = 0; k < frames; ++k) {
          const DetectionResult r = detector.detect(pairs[k].left, pairs[k].right);
          const StageTimings& t = r.timings;
          const double values[kStages + 1] = {t.quality_ms,      t.colour_ms,  t.contours_ms, t.rectify_ms, t.matching_ms,
                                              t.reprojection_ms, t.cluster_ms, t.fit_ms,      t.total_ms};
          for (int s = 0; s <= kStages; ++s) stage[s].push_back(values[s]);
          objects += static_cast<double>(r.objects.size());
          all_totals.push_back(t.total_ms);
          if (csv.is_open()) {
            double range = 0;
            for (const Detection& d : r.objects) range += d.range_m;
            csv << path.substr(path.find_last_of('/') + 1) << "," << k << "," << r.objects.size() << ","
                << (r.objects.empty() ? NAN : range / r.objects.size());
            for (double v : values) csv << "," << v;
            csv << "\n";
          }
        }
      }
      const std::vector<double>& totals = stage[kStages];
      const double n = static_cast<double>(totals.size());
      double mean_total = 0;
      for (double v : totals) mean_total += v;
      mean_total /= n;
      std::cout << "| " << path.substr(path.find_last_of('/') + 1) << " | " << totals.size() << " | "
                << std::fixed << std::setprecision(1) << objects / n;
      for (int s = 0; s < kStages; ++s) std::cout << " | " << std::setprecision(1) << tools::percentile(stage[s], 0.5);
      std::cout << " | " << tools::percentile(totals, 0.5) << " | " << tools::percentile(totals, 0.99) << " | "
                << std::setprecision(1) << 1000.0 / mean_total << " |\n";
      if (pace_hz > 0) {
        const int n_paced = std::max(1, static_cast<int>(3.0 * pace_hz));
        const auto start = std::chrono::steady_clock::now();
        const double cpu_start = processCpuSeconds();
        for (int i = 0; i < n_paced; ++i) {
          detector.detect(pairs[i % frames].left, pairs[i % frames].right);
          std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                    std::chrono::duration<double>((i + 1) / pace_hz)));
        }
        const double cpu = processCpuSeconds() - cpu_start;
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::ostringstream line;
        line << std::fixed << std::setprecision(1) << "| " << path.substr(path.find_last_of('/') + 1) << " | " << pace_hz
             << " | " << 1000.0 * cpu / n_paced << " | " << std::setprecision(2) << cpu / wall << " |";
        paced.push_back(line.str());
      }
    }
    if (!paced.empty()) {
      std::cout << "\n| scene | paced at [Hz] | CPU per pair [ms] | CPU [cores] |\n|---|---|---|---|\n";
      for (const std::string& line : paced) std::cout << line << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "benchmark_detector: " << e.what() << "\n";
    return 1;
  }
  if (summary) {
    double mean = 0;
    for (double v : all_totals) mean += v;
    mean /= static_cast<double>(all_totals.size());
    std::cout << "\nmedian_ms=" << std::setprecision(1) << tools::percentile(all_totals, 0.5)
              << " p99_ms=" << tools::percentile(all_totals, 0.99) << " pairs_per_s=" << 1000.0 / mean << "\n";
  }
  return 0;
}
