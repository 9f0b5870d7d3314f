// SPDX-License-Identifier: BSD-3-Clause
// Runs the detector on image files and prints one JSON object per detection per line.
#include <glob.h>
#include <ros/package.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/common/calibration_yaml.h"
#include "underwater_stereo/common/whole_file.h"
#include "underwater_stereo/detection/detection_json.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/detection/image_file.h"
#include "tool_helpers.h"

using namespace underwater_stereo;

namespace {

const char* kUsage =
    "usage: detect_files [--config detector.yaml] --left L --right R --left-info left.yaml --right-info right.yaml\n"
    "       detect_files [--config detector.yaml] --image X [--image Y ...]\n"
    "       detect_files [--config detector.yaml] [--left-info .. --right-info ..] --list FILE\n"
    "  --left/--right  image files or quoted glob patterns ('dir/left_*.png'); matched in sorted order (a file\n"
    "                  named as written that the pattern does not match, such as 'img[1].png', is that file)\n"
    "  --left-info     camera_info YAML as camera_calibration writes it (also --right-info)\n"
    "  --image         2D only: no right image, no calibration (colour, outline, roi, quality); repeatable\n"
    "  --list          a text file, one frame per line: 'LEFT RIGHT' (stereo) or 'IMAGE' (2D); # comments;\n"
    "                  a path with spaces in double quotes (inside them a backslash escapes the next character)\n"
    "  --config        detector configuration (default: the package's config/detector.yaml)\n"
    "  --explain       also one line per region looked at and not reported, with why: {\"file\", \"rejected\":\n"
    "                  {\"colour\", \"roi\", \"confidence\", \"stage\", \"reason\"}}\n"
    "Prints one JSON object per line per detection (DetectedObject field names plus the frame's quality),\n"
    "or one line with \"id\": null for a frame without detections; each frame's lines are written as soon as\n"
    "it is done. Unreadable, truncated or corrupt images, and images whose size the detector cannot take\n"
    "(or that differs from the calibration's), are reported on stderr naming the file and skipped; the other\n"
    "frames are still reported and the exit status is then 1 (so too a pair whose two images are the same).\n"
    "A standard output that cannot be written (disk full) stops the run, exit 1. Bad options, configuration or\n"
    "calibration: exit 2, nothing processed. An unexpected internal error: exit 3. 16-bit images are read scaled to 8 bits,\n"
    "floating-point ones (TIFF) as brightness 0..1 (one whose median pixel exceeds 1 is skipped as scaled\n"
    "otherwise); CMYK JPEGs as OpenCV reads them; a grey image is searched and said on stderr to hold no colour.\n";

struct Options {
  std::string config, left_info, right_info, list;
  std::vector<std::string> left, right, images;
  bool explain = false;
};

/// The files `pattern` (given as `option`) matches, in sorted order; a plain name as it is (a missing file is
/// reported when read). A file named as the pattern is written that the pattern does not match (img[1].png: the
/// pattern matches img1.png) is that file, said on stderr when the pattern matches others.
/// @throw std::invalid_argument when a pattern matches nothing.
std::vector<std::string> expand(const std::string& option, const std::string& pattern) {
  if (pattern.find_first_of("*?[") == std::string::npos) return {pattern};
  glob_t g{};
  std::vector<std::string> out;
  if (::glob(pattern.c_str(), 0, nullptr, &g) == 0) {
    for (std::size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
  }
  ::globfree(&g);
  std::error_code error;
  if (std::filesystem::exists(pattern, error) && std::find(out.begin(), out.end(), pattern) == out.end()) {
    if (!out.empty()) {
      std::cerr << "detect_files: " << option << " '" << pattern << "' is taken as the file of that name, not as the "
                << "pattern (which matches " << out.front() << (out.size() > 1 ? " and others" : "") << ")" << std::endl;
    }
    return {pattern};
  }
  if (out.empty()) throw std::invalid_argument(option + " '" + pattern + "': no file matches the pattern");
  return out;
}

/// The paths on one line of a --list file: words separated by spaces or tabs; a word in double quotes may hold spaces
/// (inside it, a backslash makes the next character plain: \" and \\). @throw std::invalid_argument naming what it
/// cannot read as meant: a quote not closed, text glued to a closing quote (`"a""b c"`), a quote inside an unquoted
/// word (`a"b c"`), an empty quoted path, a # after a path (a comment takes a line of its own).
std::vector<std::string> listWords(const std::string& line) {
  std::vector<std::string> words;
  const auto space = [&](std::size_t k) { return std::isspace(static_cast<unsigned char>(line[k])) != 0; };
  for (std::size_t i = 0;;) {
    while (i < line.size() && space(i)) ++i;
    if (i == line.size()) return words;
    std::string word;
    if (line[i] == '"') {
      bool closed = false;
      for (++i; i < line.size() && !closed; ++i) {
        if (line[i] == '\\' && i + 1 < line.size()) word += line[++i];
        else if (line[i] == '"') closed = true;
        else word += line[i];
      }
      if (!closed) throw std::invalid_argument("a double quote not closed");
      if (i < line.size() && !space(i)) {
        throw std::invalid_argument("text right after a closing double quote (paths are separated by spaces)");
      }
      if (word.empty()) throw std::invalid_argument("an empty path (\"\")");
    } else {
      if (line[i] == '#' && !words.empty()) {
        throw std::invalid_argument("a comment after a path (a comment takes a line of its own; a path that begins "
                                    "with # goes in double quotes)");
      }
      for (; i < line.size() && !space(i); ++i) {
        if (line[i] == '"') {
          throw std::invalid_argument("a double quote inside a word (a path with spaces goes in double quotes as a "
                                      "whole; a quote within a path as \\\")");
        }
        word += line[i];
      }
    }
    words.push_back(word);
  }
}

Options parse(int argc, char** argv) {
  Options o;
  underwater_stereo::tools::OptionsGiven given({"--left", "--right", "--image"});
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      std::exit(0);
    }
    if (arg == "--explain") {
      o.explain = true;
      continue;
    }
    static const char* const kValued[] = {"--config", "--left", "--right", "--left-info", "--right-info", "--image",
                                          "--list"};
    if (std::find(std::begin(kValued), std::end(kValued), arg) == std::end(kValued)) {
      if (arg.rfind("-", 0) == 0) throw std::invalid_argument("unknown option " + arg);
      throw std::invalid_argument("stray argument '" + arg + "': images go after --image, --left or --right (one " +
                                  "file or one quoted pattern each)");
    }
    given.add(arg);
    if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
    const std::string value = argv[++i];
    auto append = [&](std::vector<std::string>& to) {
      for (auto& f : expand(arg, value)) to.push_back(f);
    };
    if (arg == "--config") o.config = value;
    else if (arg == "--left") append(o.left);
    else if (arg == "--right") append(o.right);
    else if (arg == "--left-info") o.left_info = value;
    else if (arg == "--right-info") o.right_info = value;
    else if (arg == "--image") append(o.images);
    else o.list = value;
  }
  if (!o.list.empty()) {
    std::istringstream in;
    try {
      in.str(readWholeFile(o.list));
    } catch (const UnreadableFile& e) {
      throw std::invalid_argument("cannot read the list file " + o.list + ": " + e.reason() +
                                  " (give a text file naming one frame per line)");
    }
    std::string line;
    const std::size_t listed = o.images.size() + o.left.size();
    for (int n = 1; std::getline(in, line); ++n) {
      if (n == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark, not a path
      if (!line.empty() && line.back() == '\r') line.pop_back();          // a list written on Windows
      const std::size_t first = line.find_first_not_of(" \t");
      if (first == std::string::npos || line[first] == '#') continue;  // blank, or a comment (indented too)
      const std::string where = o.list + ":" + std::to_string(n);
      if (line.find('\0') != std::string::npos) throw std::invalid_argument(where + ": a NUL byte (no path holds one)");
      std::vector<std::string> words;
      try {
        words = listWords(line);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(where + ": " + e.what());
      }
      if (words.empty()) continue;  // white space other than spaces and tabs
      if (words.size() > 2) {
        throw std::invalid_argument(where + ": more than two files (a path with spaces goes in double quotes)");
      }
      if (words.size() == 1) {
        o.images.push_back(words[0]);
      } else {
        o.left.push_back(words[0]);
        o.right.push_back(words[1]);
      }
    }
    if (o.images.size() + o.left.size() == listed) {
      throw std::invalid_argument("the list file " + o.list + " names no frame (one 'LEFT RIGHT' or 'IMAGE' per line)");
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

/// Both cameras' calibration files, each checked on its own (naming its file), then as a pair.
StereoCalibration readCalibrations(const std::string& left_path, const std::string& right_path) {
  StereoCalibration c{loadCameraCalibrationFile(left_path), loadCameraCalibrationFile(right_path)};
  const auto problems = c.validate();
  if (!problems.empty()) throw std::invalid_argument(joinProblems(left_path + " / " + right_path, problems));
  return c;
}

/// Reads a colour image; an empty Mat (and a message naming the file on stderr) when it cannot.
cv::Mat readImage(const std::string& path) {
  try {
    cv::Mat image = readImageFile(path);
    if (isGreyImage(image)) {
      std::cerr << "detect_files: " << path << ": a grey image (its three channels equal): no colour can be named in it"
                << std::endl;
    }
    return image;
  } catch (const std::exception& e) {
    std::cerr << "detect_files: " << e.what() << ", skipped" << std::endl;
    return cv::Mat();
  }
}

/// Standard output refused the results (a full disk, a closed descriptor): every later frame's would be lost too.
struct ResultsUnwritable : std::runtime_error {
  ResultsUnwritable() : std::runtime_error("the results cannot be written to standard output (disk full?)") {}
};

/// The frame's lines, written out at once (a run stopped later keeps them).
void print(const std::string& file, const DetectionResult& r, bool with_3d, bool explain) {
  if (r.looks_swapped) {
    std::cerr << "detect_files: " << file << ": left and right images look swapped (no object reported; --explain "
              << "says why)" << std::endl;
  }
  if (r.objects.empty()) std::cout << emptyFrameJson(file, r.quality) << '\n';
  for (std::size_t i = 0; i < r.objects.size(); ++i) {
    std::cout << detectionJson(file, static_cast<int>(i), r.objects[i], r.quality, with_3d) << '\n';
  }
  for (const Rejection& rejected : explain ? r.rejected : std::vector<Rejection>{}) {
    std::cout << rejectionJson(file, rejected) << '\n';
  }
  if (!tools::standardOutputWritten()) throw ResultsUnwritable();
}

/// Runs `detect` on one frame and prints its result; false (reported naming `name`) when it fails.
template <typename Detect>
bool runFrame(const std::string& name, const std::string& file, bool with_3d, bool explain, Detect detect) {
  try {
    print(file, detect(), with_3d, explain);
    return true;
  } catch (const ResultsUnwritable&) {
    throw;  // not this frame's fault: the run stops
  } catch (const std::exception& e) {  // std::invalid_argument for bad input; anything else is reported too
    std::cerr << "detect_files: " << name << ": " << e.what() << ", skipped" << std::endl;
    return false;
  }
}

int run(int argc, char** argv) {
  Options o;
  DetectorConfig config;
  std::unique_ptr<Detector> stereo, flat;
  try {
    o = parse(argc, argv);
    if (o.config.empty()) o.config = ros::package::getPath("underwater_stereo") + "/config/detector.yaml";
    config = loadDetectorConfigFile(o.config);
    flat = std::make_unique<Detector>(config);
    if (!o.left.empty()) stereo = std::make_unique<Detector>(config, readCalibrations(o.left_info, o.right_info));
    if (stereo && !stereo->workspaceNote().empty()) std::cerr << "detect_files: note: " << stereo->workspaceNote() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "detect_files: " << e.what() << "\n" << kUsage;
    return 2;
  }
  int skipped = 0;
  for (std::size_t i = 0; i < o.left.size(); ++i) {
    const cv::Mat left = readImage(o.left[i]), right = readImage(o.right[i]);
    if (left.empty() || right.empty() ||
        !runFrame(o.left[i] + " / " + o.right[i], o.left[i], true, o.explain, [&] { return stereo->detect(left, right); })) {
      ++skipped;
    }
  }
  for (const std::string& path : o.images) {
    const cv::Mat image = readImage(path);
    if (image.empty() || !runFrame(path, path, false, o.explain, [&] { return flat->detect2d(image); })) ++skipped;
  }
  if (skipped > 0) std::cerr << "detect_files: " << skipped << " frame(s) skipped" << std::endl;
  return skipped > 0 ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const ResultsUnwritable& e) {
    std::cerr << "detect_files: " << e.what() << ": stopped" << std::endl;
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "detect_files: internal error: " << e.what() << std::endl;
  } catch (...) {
    std::cerr << "detect_files: internal error (unknown exception)" << std::endl;
  }
  return 3;
}
