// SPDX-License-Identifier: BSD-3-Clause
// Runs the detector on image files and prints one JSON object per detection per line.
#include <camera_calibration_parsers/parse.h>
#include <glob.h>
#include <ros/package.h>

#include <opencv2/imgcodecs.hpp>

#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "underwater_stereo/detection/detection_json.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/ros_glue/calibration_conversions.h"

using namespace underwater_stereo;

namespace {

const char* kUsage =
    "usage: detect_files [--config detector.yaml] --left L --right R --left-info left.yaml --right-info right.yaml\n"
    "       detect_files [--config detector.yaml] --image X [--image Y ...]\n"
    "       detect_files [--config detector.yaml] [--left-info .. --right-info ..] --list FILE\n"
    "  --left/--right  image files or quoted glob patterns ('dir/left_*.png'); matched in sorted order\n"
    "  --left-info     camera_info YAML as camera_calibration writes it (also --right-info)\n"
    "  --image         2D only: no right image, no calibration (colour, outline, roi, quality); repeatable\n"
    "  --list          a text file, one frame per line: 'LEFT RIGHT' (stereo) or 'IMAGE' (2D); # comments\n"
    "  --config        detector configuration (default: the package's config/detector.yaml)\n"
    "Prints one JSON object per line per detection (DetectedObject field names plus the frame's quality),\n"
    "or one line with \"id\": null for a frame without detections. Unreadable frames are reported on\n"
    "stderr and skipped; the exit status is then 1. Bad options, configuration or calibration: exit 2.\n";

struct Options {
  std::string config, left_info, right_info, list;
  std::vector<std::string> left, right, images;
};

std::vector<std::string> expand(const std::string& pattern) {
  glob_t g{};
  std::vector<std::string> out;
  if (::glob(pattern.c_str(), 0, nullptr, &g) == 0) {
    for (std::size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
  }
  ::globfree(&g);
  if (out.empty()) out.push_back(pattern);  // not a pattern, or nothing matched: reported when read
  return out;
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      std::exit(0);
    }
    if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
    const std::string value = argv[++i];
    auto append = [&](std::vector<std::string>& to) {
      for (auto& f : expand(value)) to.push_back(f);
    };
    if (arg == "--config") o.config = value;
    else if (arg == "--left") append(o.left);
    else if (arg == "--right") append(o.right);
    else if (arg == "--left-info") o.left_info = value;
    else if (arg == "--right-info") o.right_info = value;
    else if (arg == "--image") append(o.images);
    else if (arg == "--list") o.list = value;
    else throw std::invalid_argument("unknown option " + arg);
  }
  if (!o.list.empty()) {
    std::ifstream in(o.list);
    if (!in) throw std::invalid_argument("cannot read the list file " + o.list);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream words(line);
      std::string a, b, extra;
      words >> a >> b >> extra;
      if (a.empty()) continue;
      if (!extra.empty()) throw std::invalid_argument(o.list + ":" + std::to_string(n) + ": more than two files");
      if (b.empty()) {
        o.images.push_back(a);
      } else {
        o.left.push_back(a);
        o.right.push_back(b);
      }
    }
  }
  if (o.left.size() != o.right.size()) {
    throw std::invalid_argument(std::to_string(o.left.size()) + " left images but " + std::to_string(o.right.size()) +
                                " right images");
  }
  if (o.left.empty() && o.images.empty()) throw std::invalid_argument("no images given");
  if (!o.left.empty() && (o.left_info.empty() || o.right_info.empty())) {
    throw std::invalid_argument("stereo pairs need --left-info and --right-info");
  }
  return o;
}

CameraCalibration readInfo(const std::string& path) {
  std::string name;
  sensor_msgs::CameraInfo info;
  if (!camera_calibration_parsers::readCalibration(path, name, info)) {
    throw std::invalid_argument("cannot read camera_info YAML " + path);
  }
  return ros_glue::fromCameraInfo(info);
}

/// Reads a colour image; an empty Mat (and a message on stderr) when it cannot.
cv::Mat readImage(const std::string& path) {
  const cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
  if (img.empty()) std::cerr << "detect_files: cannot read image " << path << ", skipped\n";
  return img;
}

void print(const std::string& file, const DetectionResult& r, bool with_3d) {
  if (r.objects.empty()) std::cout << emptyFrameJson(file, r.quality) << '\n';
  for (std::size_t i = 0; i < r.objects.size(); ++i) {
    std::cout << detectionJson(file, static_cast<int>(i), r.objects[i], r.quality, with_3d) << '\n';
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  DetectorConfig config;
  std::unique_ptr<Detector> stereo, flat;
  try {
    o = parse(argc, argv);
    if (o.config.empty()) o.config = ros::package::getPath("underwater_stereo") + "/config/detector.yaml";
    config = loadDetectorConfigFile(o.config);
    flat = std::make_unique<Detector>(config);
    if (!o.left.empty()) {
      StereoCalibration calibration{readInfo(o.left_info), readInfo(o.right_info)};
      stereo = std::make_unique<Detector>(config, calibration);
    }
  } catch (const std::exception& e) {
    std::cerr << "detect_files: " << e.what() << "\n" << kUsage;
    return 2;
  }
  int skipped = 0;
  for (std::size_t i = 0; i < o.left.size(); ++i) {
    const cv::Mat left = readImage(o.left[i]), right = readImage(o.right[i]);
    if (left.empty() || right.empty()) {
      ++skipped;
      continue;
    }
    try {
      print(o.left[i], stereo->detect(left, right), true);
    } catch (const std::invalid_argument& e) {
      std::cerr << "detect_files: " << o.left[i] << " / " << o.right[i] << ": " << e.what() << ", skipped\n";
      ++skipped;
    }
  }
  for (const std::string& path : o.images) {
    const cv::Mat image = readImage(path);
    if (image.empty()) {
      ++skipped;
      continue;
    }
    print(path, flat->detect2d(image), false);
  }
  std::cout.flush();
  return skipped > 0 ? 1 : 0;
}
