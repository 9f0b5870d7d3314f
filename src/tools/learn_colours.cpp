// SPDX-License-Identifier: BSD-3-Clause
// learn_colours: learns the designated colours from labelled frames (Pascal VOC boxes) and writes a complete
// detector configuration using the learnt colour model; reports k-fold cross-validation by frame.
#include <dirent.h>
#include <yaml-cpp/yaml.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/detection/colour_learning.h"
#include "underwater_stereo/detection/detector.h"

using namespace underwater_stereo;

namespace {

const char* kUsage =
    "usage: learn_colours --images DIR --annotations DIR --out FILE.yaml [--base detector.yaml] [options]\n"
    "  Learns every designated colour from labelled frames and writes a complete detector configuration\n"
    "  (the base's other settings kept) with its colour model beside it (FILE.colour_model.yml.gz).\n"
    "  --images DIR        frames (.jpg, .jpeg, .png, .bmp); DIR may be repeated with --annotations in pairs\n"
    "  --annotations DIR   Pascal VOC XML per frame, same name (N.jpg -> N.xml); a label '<colour>' or\n"
    "                      '<anything>_<colour>' (buoy_red) teaches that colour, every other pixel is background\n"
    "  --base FILE         configuration to start from (default: the package's config/detector.yaml)\n"
    "  --colours a,b       colours to learn (default: the base's designated colours)\n"
    "  --background a,b    other label names, learnt as background (any other name is an error)\n"
    "  --folds K           cross-validation folds by frame (default 5; 1 = none)\n"
    "  --seed S            fold assignment and forest seed (default 1)\n"
    "  --min-label-px N    labels shorter than this are beyond the working range: neither (default 15)\n"
    "  --augment N         also learn from N copies of each frame seen through other water (default 2)\n"
    "  --trees N, --max-depth N, --balance X, --min-confidence X   model settings (100, 10, 0.6, base's)\n"
    "  --sweep a,b,...     also cross-validated recall and false detections at these min_confidence values\n"
    "                      (one table; from the same folds, to choose min_confidence)\n"
    "Exit status: 0 written, 1 bad labels or images, 2 bad options or configuration.\n";

struct Options {
  std::vector<std::string> images, annotations;
  std::string out, base;
  LearningOptions learning;
  int folds = 5;
  double min_confidence = -1;
  std::vector<double> sweep;
  bool colours_given = false;
};

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) out.push_back(item);
  }
  return out;
}

/// `text` as a number in [lo, hi]; otherwise an error that starts with `what`.
double numberIn(const std::string& text, double lo, double hi, const std::string& what) {
  std::size_t used = 0;
  double x = 0;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != text.size() || !(x >= lo && x <= hi)) {
    throw std::invalid_argument(what + ": expected a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return x;
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
    const std::string v = argv[++i];
    auto number = [&](double lo, double hi) { return numberIn(v, lo, hi, arg + " " + v); };
    if (arg == "--images") o.images.push_back(v);
    else if (arg == "--annotations") o.annotations.push_back(v);
    else if (arg == "--out") o.out = v;
    else if (arg == "--base") o.base = v;
    else if (arg == "--colours") { o.learning.colours = split(v); o.colours_given = true; }
    else if (arg == "--background") o.learning.background_labels = split(v);
    else if (arg == "--folds") o.folds = static_cast<int>(number(1, 100));
    else if (arg == "--seed") o.learning.training.seed = static_cast<int>(number(0, 2e9));
    else if (arg == "--augment") o.learning.augment = static_cast<int>(number(0, 20));
    else if (arg == "--min-label-px") o.learning.min_label_px = static_cast<int>(number(1, 10000));
    else if (arg == "--trees") o.learning.training.trees = static_cast<int>(number(1, 2000));
    else if (arg == "--max-depth") o.learning.training.max_depth = static_cast<int>(number(1, 30));
    else if (arg == "--balance") o.learning.training.balance = number(0, 1);
    else if (arg == "--min-confidence") o.min_confidence = number(0.01, 1);
    else if (arg == "--sweep") {
      for (const std::string& item : split(v)) o.sweep.push_back(numberIn(item, 0.01, 1, "--sweep " + v + ": '" + item + "'"));
      if (o.sweep.empty()) throw std::invalid_argument("--sweep needs at least one value");
    }
    else throw std::invalid_argument("unknown option " + arg);
  }
  if (o.images.empty() || o.images.size() != o.annotations.size()) {
    throw std::invalid_argument("give --images DIR --annotations DIR (in pairs)");
  }
  if (o.out.empty()) throw std::invalid_argument("give --out FILE.yaml");
  if (!o.sweep.empty() && o.folds < 2) throw std::invalid_argument("--sweep needs cross-validation (--folds 2 or more)");
  return o;
}

std::vector<std::string> imagesIn(const std::string& dir) {
  std::vector<std::string> out;
  DIR* d = ::opendir(dir.c_str());
  if (!d) throw std::invalid_argument("--images " + dir + ": not a readable folder");
  while (const dirent* e = ::readdir(d)) {
    const std::string name = e->d_name;
    const std::size_t dot = name.find_last_of('.');
    if (dot == std::string::npos) continue;
    std::string ext = name.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext == "jpg" || ext == "jpeg" || ext == "png" || ext == "bmp") out.push_back(name);
  }
  ::closedir(d);
  std::sort(out.begin(), out.end());
  return out;
}

/// Every frame of every folder pair; every problem (unreadable image or XML, missing annotation) listed.
std::vector<LabelledFrame> readFrames(const Options& o) {
  std::vector<LabelledFrame> frames;
  std::vector<std::string> problems;
  for (std::size_t d = 0; d < o.images.size(); ++d) {
    for (const std::string& name : imagesIn(o.images[d])) {
      LabelledFrame f;
      f.name = o.images[d] + "/" + name;
      f.image = cv::imread(f.name, cv::IMREAD_COLOR);
      if (f.image.empty()) {
        problems.push_back(f.name + ": cannot be read as an image");
        continue;
      }
      const std::string xml = o.annotations[d] + "/" + name.substr(0, name.find_last_of('.')) + ".xml";
      try {
        f.labels = readVocLabels(xml);
      } catch (const std::invalid_argument& e) {
        problems.push_back(e.what());
        continue;
      }
      frames.push_back(std::move(f));
    }
  }
  if (frames.empty() && problems.empty()) problems.push_back("no images found in the --images folders");
  if (!problems.empty()) throw std::runtime_error(joinProblems("cannot learn from these frames", problems));
  return frames;
}

ColourModel trainOn(const std::vector<const FrameSamples*>& parts, const LearningOptions& options) {
  cv::Mat features;
  std::vector<int> labels;
  for (const FrameSamples* p : parts) {
    if (p->features.empty()) continue;
    features.push_back(p->features);
    labels.insert(labels.end(), p->labels.begin(), p->labels.end());
  }
  return ColourModel::train(features, labels, options.colours, options.training);
}

void printScore(const LearningScore& s, const LearningOptions& options, const std::string& heading) {
  std::printf("\n%s\n\n| colour | labelled | found | recall %% |\n|---|---|---|---|\n", heading.c_str());
  for (std::size_t k = 0; k < options.colours.size(); ++k) {
    std::printf("| %s | %d | %d | %.1f |\n", options.colours[k].c_str(), s.labelled[k], s.found[k],
                s.labelled[k] ? 100.0 * s.found[k] / s.labelled[k] : 0.0);
  }
  const int labelled = std::accumulate(s.labelled.begin(), s.labelled.end(), 0);
  const int found = std::accumulate(s.found.begin(), s.found.end(), 0);
  std::printf("| **all** | %d | %d | %.1f |\n\nunlabelled or false detections: %d in %d frames (%.2f per frame)\n",
              labelled, found, 100.0 * s.recall(), s.false_detections, s.frames,
              s.frames ? double(s.false_detections) / s.frames : 0.0);
  std::printf("\nconfusion (rows: labelled colour; columns: detected colour at the label, or missed)\n\n| |");
  for (const auto& c : options.colours) std::printf(" %s |", c.c_str());
  std::printf(" missed |\n|---|");
  for (std::size_t k = 0; k <= options.colours.size(); ++k) std::printf("---|");
  std::printf("\n");
  for (std::size_t k = 0; k < options.colours.size(); ++k) {
    std::printf("| %s |", options.colours[k].c_str());
    for (int v : s.confusion[k]) std::printf(" %d |", v);
    std::printf("\n");
  }
}

std::string formatted(double x) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f", x);
  return text;
}

/// One line per threshold: recall per colour and overall, false detections per frame.
void printSweep(const std::vector<double>& thresholds, const std::vector<LearningScore>& totals,
                const LearningOptions& options) {
  std::printf("\ncross-validated by min_confidence (recall %%)\n\n| min_confidence |");
  for (const auto& c : options.colours) std::printf(" %s |", c.c_str());
  std::printf(" all | false per frame |\n|---|");
  for (std::size_t k = 0; k < options.colours.size() + 2; ++k) std::printf("---|");
  std::printf("\n");
  for (std::size_t t = 0; t < thresholds.size(); ++t) {
    const LearningScore& s = totals[t];
    std::printf("| %.2f |", thresholds[t]);
    for (std::size_t k = 0; k < options.colours.size(); ++k) {
      std::printf(" %.1f |", s.labelled[k] ? 100.0 * s.found[k] / s.labelled[k] : 0.0);
    }
    std::printf(" %.1f | %.2f |\n", 100.0 * s.recall(), s.frames ? double(s.false_detections) / s.frames : 0.0);
  }
}

/// The base configuration file with the learnt colours and model, as YAML.
void writeConfig(const std::string& base_path, const std::string& out, const std::string& model_name,
                 const LearningOptions& options, double min_confidence) {
  YAML::Node root = YAML::LoadFile(base_path);
  YAML::Node colours(YAML::NodeType::Sequence);
  for (const std::string& name : options.colours) {
    YAML::Node entry;
    for (const auto& c : root["colours"]) {
      if (c["name"] && c["name"].as<std::string>() == name) entry = YAML::Clone(c);
    }
    if (!entry) entry["name"] = name;
    entry.SetStyle(YAML::EmitterStyle::Flow);
    colours.push_back(entry);
  }
  root["colours"] = colours;
  root["candidates"]["source"] = "learned";
  root["colour_model"]["file"] = model_name;
  if (min_confidence > 0) root["colour_model"]["min_confidence"] = min_confidence;
  std::ofstream file(out);
  file << "# Learnt by learn_colours from labelled frames (see README, 'A new pool'); the colour model is in "
       << model_name << ".\n"
       << YAML::Dump(root) << "\n";
  if (!file) throw std::runtime_error(out + ": cannot be written");
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  DetectorConfig base;
  try {
    o = parse(argc, argv);
    if (o.base.empty()) o.base = std::string(UWS_SOURCE_DIR) + "/config/detector.yaml";
    base = loadDetectorConfigFile(o.base);
    if (!o.colours_given) {
      for (const ColourClass& c : base.colours.classes) o.learning.colours.push_back(c.name);
    }
    const auto problems = o.learning.validate();
    if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid options", problems));
  } catch (const std::exception& e) {
    std::cerr << "learn_colours: " << e.what() << "\n" << kUsage;
    return 2;
  }
  try {
    const std::vector<LabelledFrame> frames = readFrames(o);
    checkLabels(frames, o.learning);
    // Proposals are the detector's own, with the base's search settings.
    DetectorConfig proposer_config = base;
    proposer_config.candidates.source = ContourSource::kColourMask;
    const Detector proposer(proposer_config);
    std::vector<FrameSamples> samples;
    for (std::size_t i = 0; i < frames.size(); ++i) {
      samples.push_back(samplesOf(frames[i], proposer, o.learning, static_cast<unsigned>(i + 1)));
    }
    int objects = 0, proposed = 0;
    for (const FrameSamples& s : samples) {
      objects += s.objects;
      proposed += s.proposed;
    }
    std::printf("%zu frames; the detector's proposals cover %d of %d labelled objects (the most it can find)\n",
                frames.size(), proposed, objects);
    const double min_confidence = o.min_confidence > 0 ? o.min_confidence : base.learned.min_confidence;
    auto configWith = [&](const ColourModel& m, double confidence) {
      DetectorConfig c = learnedConfig(base, o.out, std::make_shared<const ColourModel>(m), o.learning);
      c.learned.min_confidence = confidence;
      return c;
    };
    if (o.folds > 1) {
      // One detection pass per fold at the lowest threshold asked for, scored at each (scoreAt).
      std::vector<double> thresholds = o.sweep;
      thresholds.push_back(min_confidence);
      std::sort(thresholds.begin(), thresholds.end());
      thresholds.erase(std::unique(thresholds.begin(), thresholds.end()), thresholds.end());
      std::vector<int> fold(frames.size());
      std::iota(fold.begin(), fold.end(), 0);
      std::mt19937 rng(static_cast<unsigned>(o.learning.training.seed));
      std::shuffle(fold.begin(), fold.end(), rng);
      std::vector<LearningScore> totals(thresholds.size());
      for (int k = 0; k < o.folds; ++k) {
        std::vector<const FrameSamples*> train;
        std::vector<LabelledFrame> held_out;
        for (std::size_t i = 0; i < frames.size(); ++i) {
          if (fold[i] % o.folds == k) held_out.push_back(frames[i]);
          else train.push_back(&samples[i]);
        }
        const Detector fold_detector(configWith(trainOn(train, o.learning), thresholds.front()));
        const std::vector<LearningScore> scores = scoreAt(fold_detector, held_out, o.learning, thresholds);
        for (std::size_t t = 0; t < thresholds.size(); ++t) totals[t].add(scores[t]);
      }
      const std::size_t chosen = std::find(thresholds.begin(), thresholds.end(), min_confidence) - thresholds.begin();
      printScore(totals[chosen], o.learning,
                 std::to_string(o.folds) + "-fold cross-validation by frame (" + std::to_string(frames.size()) +
                     " frames; labels under " + std::to_string(o.learning.min_label_px) +
                     " px tall not counted; min_confidence " + formatted(min_confidence) + ")");
      if (!o.sweep.empty()) printSweep(thresholds, totals, o.learning);
    }
    std::vector<const FrameSamples*> all;
    for (const FrameSamples& s : samples) all.push_back(&s);
    const ColourModel model = trainOn(all, o.learning);
    std::string stem = o.out;
    if (stem.size() > 5 && stem.substr(stem.size() - 5) == ".yaml") stem.resize(stem.size() - 5);
    const std::string model_path = stem + ".colour_model.yml.gz";  // FileStorage gzips it (a forest is ~3 MB as text)
    model.save(model_path);
    writeConfig(o.base, o.out, model_path.substr(model_path.find_last_of('/') + 1), o.learning, o.min_confidence);
    loadDetectorConfigFile(o.out);  // what was written must load
    std::printf("\nwrote %s and %s\n", o.out.c_str(), model_path.c_str());
  } catch (const std::exception& e) {
    std::cerr << "learn_colours: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
