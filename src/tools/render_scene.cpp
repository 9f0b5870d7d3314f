// SPDX-License-Identifier: BSD-3-Clause
// render_scene: renders a simulated scene file into a rosbag (images, camera_info, ground truth) and/or
// PNG pairs with camera_info YAML files, for offline use; or sampled scenes as training data for a colour
// learner (left images, Pascal VOC boxes and per-pixel label masks from the exact truth).
#include <camera_calibration_parsers/parse.h>
#include <cv_bridge/cv_bridge.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <ros/names.h>
#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/ros_glue/calibration_conversions.h"
#include "underwater_stereo/ros_glue/ground_truth_conversions.h"
#include "underwater_stereo/sim/renderer.h"
#include "underwater_stereo/sim/scene_sampler.h"
#include "underwater_stereo/sim/voc_labels.h"
#include "render_problem.h"
#include "sampler_options.h"
#include "tool_helpers.h"

namespace {

const char* kUsage =
    "usage: render_scene --scene SCENE.yaml [--frames N] [--rate HZ] [--bag OUT.bag] [--png-dir DIR]\n"
    "                    [--namespace stereo] [--start-time SECONDS]\n"
    "       render_scene --random N [--seed S] --out DIR [--size WxH] [--luma LO,HI] [--focal-mm LO,HI]\n"
    "                    [--baseline-m LO,HI]\n"
    "  Renders frames 0..N-1 (scene time k/HZ) of SCENE.yaml.\n"
    "  --bag      writes <ns>/left/image_raw, <ns>/left/camera_info, <ns>/right/..., <ns>/ground_truth\n"
    "  --png-dir  writes left_NNNN.png / right_NNNN.png (demosaiced BGR), left.yaml / right.yaml\n"
    "             (camera_calibration format) and ground_truth.yaml; frame images of an earlier render there\n"
    "             are removed first\n"
    "  --random   renders the scenes sampled from seeds S..S+N-1 (default S = 1000) and writes, per seed (id = the\n"
    "             seed, 6 digits), DIR/images/<id>.png (left, demosaiced BGR), DIR/annotations/<id>.xml (Pascal\n"
    "             VOC: one <object> per visible red/orange/yellow/green object, <name> = its colour; <difficult>\n"
    "             when under 400 px) and DIR/masks/<id>.png (0 background, k = the XML's k-th <object>).\n"
    "             Distractors (other colours) are background.\n"
    "  --luma     the mean luma (BT.601, 1-254) each sampled scene is exposed to, drawn from [LO, HI] (default\n"
    "             30,200: the sampler's range); e.g. 12,40 for dark water.\n"
    "  --focal-mm, --baseline-m  each sampled scene's lens focal length (in air) and baseline drawn from [LO, HI]\n"
    "             instead of the head's 8 mm and 0.12 m (other optics).\n";

struct Options {
  std::string scene, bag, png_dir, ns = "stereo", out_dir;
  int frames = 1;
  int random = 0;
  long long seed = 1000;
  underwater_stereo::sim::SceneSamplerConfig sampler;
  double rate_hz = 15.0;
  double start_time_s = 1.6e9;
};

/// The rendered `image` (in `encoding`) as BGR8, demosaiced by cv_bridge: the judge's pictures are not made by the
/// judged code (detection/'s RawFrame).
cv::Mat demosaiced(const cv::Mat& image, const std::string& encoding) {
  return cv_bridge::cvtColor(boost::make_shared<cv_bridge::CvImage>(std_msgs::Header(), encoding, image), "bgr8")->image;
}

bool parse(int argc, char** argv, Options& o, std::string& error) {
  namespace tools = underwater_stereo::tools;
  tools::SamplerOptions sampler_given;
  tools::OptionsGiven given;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") return false;
    try {
      given.add(arg);
    } catch (const std::invalid_argument& e) {
      error = e.what();
      return false;
    }
    if (i + 1 >= argc) {
      error = arg + " needs a value";
      return false;
    }
    const std::string value = argv[++i];
    try {
      if (arg == "--scene") o.scene = value;
      else if (arg == "--bag") o.bag = value;
      else if (arg == "--png-dir") o.png_dir = value;
      else if (arg == "--namespace") o.ns = value;
      else if (arg == "--frames") o.frames = static_cast<int>(tools::wholeNumberIn(value, 1, 1000000, arg));
      else if (arg == "--rate") o.rate_hz = tools::numberIn(value, 1e-3, 1e3, arg);
      else if (arg == "--start-time") o.start_time_s = tools::numberIn(value, 0, 4294967295.999, arg);
      else if (arg == "--random") o.random = static_cast<int>(tools::wholeNumberIn(value, 1, 10000000, arg));
      else if (arg == "--seed") o.seed = tools::wholeNumberIn(value, 0, 1LL << 62, arg);
      else if (arg == "--out") o.out_dir = value;
      else if (sampler_given.takes(arg)) {
        error = sampler_given.read(arg, value, o.sampler);
        if (!error.empty()) return false;
      } else {
        error = "unknown option " + arg;
        return false;
      }
    } catch (const std::invalid_argument& e) {
      error = e.what();
      return false;
    }
  }
  // An option of the other mode would be ignored: refused instead, naming the mode it goes with.
  static const std::vector<std::string> kRandomOnly{"--random", "--seed", "--out", "--size", "--luma",
                                                    "--focal-mm", "--baseline-m"};
  static const std::vector<std::string> kSceneOnly{"--scene", "--bag", "--png-dir", "--namespace", "--frames", "--rate",
                                                   "--start-time"};
  const bool random = o.random != 0;
  for (const std::string& option : given.options()) {
    const std::vector<std::string>& other = random ? kSceneOnly : kRandomOnly;
    if (std::find(other.begin(), other.end(), option) != other.end()) {
      // --scene and --random themselves name the two modes: given together, they are said to exclude each other.
      error = option == "--scene" || option == "--random"
                  ? "--scene and --random N are two modes: give one of them"
                  : option + (random ? " goes with --scene, not with --random" : " goes with --random N, not with --scene");
      return false;
    }
  }
  if (random) {
    if (o.out_dir.empty()) error = "--random needs --out DIR";
    else error = sampler_given.problem(o.sampler);
    return error.empty();
  }
  if (o.scene.empty()) error = "--scene is required";
  else if (o.bag.empty() && o.png_dir.empty()) error = "give --bag and/or --png-dir";
  else if (std::string why; !ros::names::validate(o.ns, why)) error = "--namespace '" + o.ns + "': " + why;
  // ros::names::validate lets an empty segment and a private name through: neither makes a topic in a bag.
  else if (o.ns.find("//") != std::string::npos || (!o.ns.empty() && o.ns[0] == '~')) {
    error = "--namespace '" + o.ns + "': no empty segment ('//') and no private name ('~')";
  }
  // ros::Time holds 0 .. 2^32 s; the last frame's stamp must fit too.
  else if (!(o.start_time_s + (o.frames - 1) / o.rate_hz < 4294967296.0)) {
    error = "the last frame's stamp (--start-time + (--frames - 1) / --rate = " +
            std::to_string(o.start_time_s + (o.frames - 1) / o.rate_hz) + " s) must lie below 2^32 s";
  }
  return error.empty();
}

YAML::Node groundTruthYaml(const underwater_stereo::sim::GroundTruthObject& g) {
  YAML::Node n;
  n["name"] = g.name;
  n["shape"] = g.shape;
  n["colour"] = g.colour;
  n["size_m"] = std::vector<double>{g.size_m.x(), g.size_m.y(), g.size_m.z()};
  n["position_m"] = std::vector<double>{g.centre_left_m.x(), g.centre_left_m.y(), g.centre_left_m.z()};
  n["orientation_xyzw"] =
      std::vector<double>{g.orientation_left.x(), g.orientation_left.y(), g.orientation_left.z(), g.orientation_left.w()};
  n["range_m"] = g.range_m;
  n["visible_pixels"] = g.visible_pixels;
  n["roi_xywh"] = std::vector<int>{g.roi_left.x, g.roi_left.y, g.roi_left.width, g.roi_left.height};
  return n;
}

/// Removes the frame images an earlier render left in `dir` (left_NNNN.png / right_NNNN.png, 4 or more digits:
/// this tool's names, nothing else), so that the directory holds this render's frames only; returns how many.
int removeEarlierFrames(const std::string& dir) {
  static const std::regex kFrame("(left|right)_[0-9]{4,}\\.png");  // %04d: five digits from frame 10000
  int removed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.is_regular_file() && std::regex_match(entry.path().filename().string(), kFrame)) {
      std::filesystem::remove(entry.path());
      ++removed;
    }
  }
  return removed;
}

/// Training data for a colour learner from the sampled scenes of seeds opt.seed .. opt.seed + opt.random - 1.
void writeTrainingData(const Options& opt) {
  using namespace underwater_stereo;
  namespace fs = std::filesystem;
  const fs::path out(opt.out_dir);
  for (const char* sub : {"images", "annotations", "masks"}) fs::create_directories(out / sub);
  const sim::Renderer head(sim::sampleScene(static_cast<std::uint64_t>(opt.seed), opt.sampler).scene);
  for (int i = 0; i < opt.random; ++i) {
    const auto seed = static_cast<std::uint64_t>(opt.seed + i);
    const sim::SampledScene sampled = sim::sampleScene(seed, opt.sampler);
    const sim::RenderedPair pair = tools::SamplerOptions::headFor(opt.sampler, head, sampled.scene).render(0.0, 0);
    const std::vector<std::size_t> labelled = sim::labelledObjects(pair.ground_truth, opt.sampler.designated);
    char id[32];
    std::snprintf(id, sizeof(id), "%06llu", static_cast<unsigned long long>(seed));
    const std::string image = std::string(id) + ".png";
    const cv::Mat bgr = demosaiced(pair.left, pair.encoding);
    if (!cv::imwrite((out / "images" / image).string(), bgr) ||
        !cv::imwrite((out / "masks" / image).string(), sim::labelMask(pair.left_labels, labelled))) {
      throw std::runtime_error("cannot write " + image + " into " + opt.out_dir);
    }
    std::ofstream xml(out / "annotations" / (std::string(id) + ".xml"));
    xml << sim::vocAnnotation(image, bgr.size(), pair.ground_truth, labelled, 400);
    if (!xml) throw std::runtime_error(std::string("cannot write annotations/") + id + ".xml into " + opt.out_dir);
    std::cout << id << ": " << labelled.size() << " labelled object(s)" << std::endl;
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace underwater_stereo;
  Options opt;
  std::string error;
  if (!parse(argc, argv, opt, error)) {
    if (!error.empty()) std::cerr << "render_scene: " << error << "\n";
    std::cerr << kUsage;
    return error.empty() ? 0 : 2;
  }
  try {
    if (opt.random > 0) {
      writeTrainingData(opt);
      return 0;
    }
    // The command line named a scene that cannot be read or rendered: as a bad option, exit 2.
    std::optional<sim::Scene> scene;
    try {
      scene = sim::loadSceneFile(opt.scene);
    } catch (const std::invalid_argument& e) {  // its errors name the file
      std::cerr << "render_scene: " << e.what() << "\n";
      return 2;
    }
    std::optional<sim::Renderer> made;
    try {
      made.emplace(std::move(*scene));
    } catch (const std::invalid_argument& e) {
      std::cerr << "render_scene: " << opt.scene << ": " << e.what() << "\n";
      return 2;
    }
    // A camera that meets an object at a later frame (a moving camera or object): refused before anything is written.
    if (const std::string problem = tools::renderProblem(*made, opt.scene, opt.frames, opt.rate_hz); !problem.empty()) {
      std::cerr << "render_scene: " << problem << "\n";
      return 2;
    }
    const sim::Renderer& renderer = *made;
    const StereoCalibration& calib = renderer.calibration();
    rosbag::Bag bag;
    if (!opt.bag.empty()) bag.open(opt.bag, rosbag::bagmode::Write);
    YAML::Node truth_frames;
    if (!opt.png_dir.empty()) {
      std::filesystem::create_directories(opt.png_dir);
      const int removed = removeEarlierFrames(opt.png_dir);
      if (removed > 0) std::cout << "removed " << removed << " frame image(s) of an earlier render from " << opt.png_dir << "\n";
      const std::string base = opt.png_dir + "/";
      sensor_msgs::CameraInfo left = ros_glue::toCameraInfo(calib.left), right = ros_glue::toCameraInfo(calib.right);
      if (!camera_calibration_parsers::writeCalibration(base + "left.yaml", "left", left) ||
          !camera_calibration_parsers::writeCalibration(base + "right.yaml", "right", right)) {
        throw std::runtime_error("cannot write calibration YAML into " + opt.png_dir);
      }
    }
    const std::string prefix = opt.ns.empty() ? "" : "/" + opt.ns;
    for (int k = 0; k < opt.frames; ++k) {
      const auto started = std::chrono::steady_clock::now();
      const sim::RenderedPair pair = renderer.render(k / opt.rate_hz, static_cast<std::uint64_t>(k));
      const double render_ms =
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
      std_msgs::Header header;
      header.seq = static_cast<std::uint32_t>(k);
      header.stamp = ros::Time(opt.start_time_s + k / opt.rate_hz);
      header.frame_id = "stereo_left_optical_frame";  // both sides: stereo consumers require one frame
      if (bag.isOpen()) {
        sensor_msgs::CameraInfo info = ros_glue::toCameraInfo(calib.left);
        info.header = header;
        bag.write(prefix + "/left/image_raw", header.stamp, cv_bridge::CvImage(header, pair.encoding, pair.left).toImageMsg());
        bag.write(prefix + "/left/camera_info", header.stamp, info);
        bag.write(prefix + "/ground_truth", header.stamp,
                  ros_glue::toGroundTruthMsg(pair.ground_truth, header, pair.camera_pose, "odom"));
        tf2_msgs::TFMessage tf;
        tf.transforms.push_back(ros_glue::toCameraTransform(pair.camera_pose, header, "odom"));
        bag.write("/tf", header.stamp, tf);
        info = ros_glue::toCameraInfo(calib.right);
        info.header = header;
        bag.write(prefix + "/right/image_raw", header.stamp, cv_bridge::CvImage(header, pair.encoding, pair.right).toImageMsg());
        bag.write(prefix + "/right/camera_info", header.stamp, info);
      }
      if (!opt.png_dir.empty()) {
        char name[32];
        for (const auto& [side, image] : {std::pair<const char*, const cv::Mat&>{"left", pair.left}, {"right", pair.right}}) {
          std::snprintf(name, sizeof(name), "/%s_%04d.png", side, k);
          const cv::Mat bgr = demosaiced(image, pair.encoding);
          if (!cv::imwrite(opt.png_dir + name, bgr)) throw std::runtime_error(std::string("cannot write ") + opt.png_dir + name);
        }
        YAML::Node frame;
        frame["index"] = k;
        frame["time_s"] = pair.time_s;
        for (const auto& g : pair.ground_truth) frame["objects"].push_back(groundTruthYaml(g));
        truth_frames.push_back(frame);
      }
      std::cout << "frame " << k << " (rendered in " << std::fixed << std::setprecision(0) << render_ms << " ms)"
                << std::setprecision(3) << ":";
      for (const auto& g : pair.ground_truth) {
        std::cout << " " << g.name << " range " << g.range_m << " m, " << g.visible_pixels << " px;";
      }
      std::cout << std::endl;
    }
    if (!opt.png_dir.empty()) {
      std::ofstream truth(opt.png_dir + "/ground_truth.yaml");
      truth << truth_frames << "\n";
      if (!truth.flush()) throw std::runtime_error("cannot write ground_truth.yaml into " + opt.png_dir);
    }
  } catch (const std::exception& e) {
    std::cerr << "render_scene: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
