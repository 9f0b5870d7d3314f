// SPDX-License-Identifier: BSD-3-Clause
// learn_colours: learns the designated colours from labelled frames (Pascal VOC boxes) and writes a complete
// detector configuration using the learnt colour model; reports k-fold cross-validation by frame.
#include <dirent.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "underwater_stereo/common/whole_file.h"
#include "underwater_stereo/config/yaml_fields.h"
#include "underwater_stereo/detection/colour_learning.h"
#include "underwater_stereo/detection/detection_json.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/detection/image_file.h"
#include "underwater_stereo/detection/miss_causes.h"
#include "tool_helpers.h"

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
    "  --zoom N            and from N copies seen nearer (1.3-2x, around a labelled object; default 0)\n"
    "  --trees N, --max-depth N, --balance X, --min-confidence X   model settings (100, 10, 0.6, base's)\n"
    "  --boosted-trees N, --boosted-depth N   boosted trees that decide object or background in place of the forest's\n"
    "                      votes (the forest still names the colour; their score is 0.5 where their votes even out,\n"
    "                      a natural --min-confidence); default 0 (none), depth 6\n"
    "  --sweep a,b,...     also cross-validated recall and false detections at these min_confidence values\n"
    "                      (one table; from the same folds, to choose min_confidence)\n"
    "  --choose-thresholds a,b,...   a min_confidence per colour from these values, chosen by cross-validation\n"
    "                      (the best mean recall per colour with at most --max-false per frame): inside each\n"
    "                      fold's training frames for its figures, on all frames for the written config\n"
    "                      (and lists where each held-out miss was lost: no proposal, too few votes, another\n"
    "                      colour, an overlapping region)\n"
    "  --max-false X       false detections per frame allowed when choosing thresholds (default 0.3)\n"
    "  --detections-out F  the cross-validated (held-out) detections as JSON lines like detect_files' (to score\n"
    "                      or draw them: scripts/evaluate_transdec --detections F)\n"
    "Exit status: 0 written, 1 bad labels or images (or a standard output that could not be written: the files\n"
    "are still written), 2 bad options or configuration.\n";

struct Options {
  std::vector<std::string> images, annotations;
  std::string out, base;
  LearningOptions learning;
  int folds = 5;
  double min_confidence = -1;
  std::vector<double> sweep;
  std::vector<double> choose;  ///< per-colour thresholds chosen from these (ascending)
  double max_false = 0.3;
  std::string detections_out;  ///< the held-out detections as JSON lines
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

/// The colour model file written beside the configuration `out` (FILE.yaml -> FILE.colour_model.yml.gz; FileStorage
/// gzips it: a forest is ~3 MB as text).
std::string modelPathOf(const std::string& out) {
  std::string stem = out;
  if (stem.size() > 5 && stem.substr(stem.size() - 5) == ".yaml") stem.resize(stem.size() - 5);
  return stem + ".colour_model.yml.gz";
}

Options parse(int argc, char** argv) {
  Options o;
  tools::OptionsGiven given({"--images", "--annotations"});
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      std::exit(0);
    }
    given.add(arg);
    if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
    const std::string v = argv[++i];
    auto number = [&](double lo, double hi) { return tools::numberIn(v, lo, hi, arg); };
    auto whole = [&](long long lo, long long hi) { return static_cast<int>(tools::wholeNumberIn(v, lo, hi, arg)); };
    if (arg == "--images") o.images.push_back(v);
    else if (arg == "--annotations") o.annotations.push_back(v);
    else if (arg == "--out") o.out = v;
    else if (arg == "--base") o.base = v;
    else if (arg == "--colours") { o.learning.colours = split(v); o.colours_given = true; }
    else if (arg == "--background") o.learning.background_labels = split(v);
    else if (arg == "--folds") o.folds = whole(1, 100);
    else if (arg == "--seed") o.learning.training.seed = whole(0, 2000000000);
    else if (arg == "--augment") o.learning.augment = whole(0, 20);
    else if (arg == "--zoom") o.learning.zoom = whole(0, 20);
    else if (arg == "--min-label-px") o.learning.min_label_px = whole(1, 10000);
    else if (arg == "--trees") o.learning.training.trees = whole(1, 2000);
    else if (arg == "--max-depth") o.learning.training.max_depth = whole(1, 30);
    else if (arg == "--balance") o.learning.training.balance = number(0, 1);
    else if (arg == "--boosted-trees") o.learning.training.boosted.trees = whole(0, 5000);
    else if (arg == "--boosted-depth") o.learning.training.boosted.depth = whole(1, 20);
    else if (arg == "--min-confidence") o.min_confidence = number(0.01, 1);
    else if (arg == "--sweep") {
      for (const std::string& item : split(v)) o.sweep.push_back(tools::numberIn(item, 0.01, 1, "--sweep " + v));
      if (o.sweep.empty()) throw std::invalid_argument("--sweep needs at least one value");
    }
    else if (arg == "--choose-thresholds") {
      for (const std::string& item : split(v)) {
        o.choose.push_back(tools::numberIn(item, 0.01, 1, "--choose-thresholds " + v));
      }
      std::sort(o.choose.begin(), o.choose.end());
      o.choose.erase(std::unique(o.choose.begin(), o.choose.end()), o.choose.end());
      if (o.choose.empty()) throw std::invalid_argument("--choose-thresholds needs at least one value");
    }
    else if (arg == "--max-false") o.max_false = number(0, 100);
    else if (arg == "--detections-out") o.detections_out = v;
    else throw std::invalid_argument("unknown option " + arg);
  }
  if (o.images.empty() || o.images.size() != o.annotations.size()) {
    throw std::invalid_argument("give --images DIR --annotations DIR (in pairs)");
  }
  tools::refuseRepeated("--images ", o.images, "its frames would be learnt twice, and judged by folds that learnt them");
  if (o.out.empty()) throw std::invalid_argument("give --out FILE.yaml");
  // Checked now, not after a cross-validation that can take many minutes.
  tools::checkWritableFile("--out", o.out, "the configuration file to write (FILE.yaml)");
  tools::checkWritableFile("--out's colour model", modelPathOf(o.out),
                           "an --out whose colour model, written beside it, can be written");
  if (!o.sweep.empty() && o.folds < 2) throw std::invalid_argument("--sweep needs cross-validation (--folds 2 or more)");
  if (!o.choose.empty() && o.folds < 2) {
    throw std::invalid_argument("--choose-thresholds needs cross-validation (--folds 2 or more)");
  }
  if (!o.detections_out.empty()) {
    if (o.folds < 2) throw std::invalid_argument("--detections-out needs cross-validation (--folds 2 or more)");
    tools::checkWritableFile("--detections-out", o.detections_out, "the JSON lines file to write");
  }
  if (!o.choose.empty() && o.min_confidence > 0) {
    throw std::invalid_argument("give --min-confidence or --choose-thresholds, not both");
  }
  const auto& options = given.options();
  if (o.learning.training.boosted.trees == 0 &&
      std::find(options.begin(), options.end(), "--boosted-depth") != options.end()) {
    throw std::invalid_argument("--boosted-depth needs --boosted-trees N (1 or more)");
  }
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

/// The .xml files in `dir` (none when it is no readable folder: the frames' own annotations are then reported
/// missing one by one).
std::vector<std::string> annotationsIn(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code error;
  for (const auto& e : std::filesystem::directory_iterator(dir, error)) {
    const std::string name = e.path().filename().string();
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".xml") == 0) out.push_back(name);
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// Adds a problem for every frame whose pixels are another's (a copy under another name or in another --images
/// folder): it would be learnt twice, and judged by folds that learnt it.
void refuseRepeatedFrames(const std::vector<LabelledFrame>& frames, std::vector<std::string>& problems) {
  std::unordered_multimap<std::size_t, std::size_t> by_hash;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const cv::Mat& image = frames[i].image;
    const cv::Mat pixels = image.isContinuous() ? image : image.clone();
    const std::size_t hash = std::hash<std::string_view>()(
        std::string_view(reinterpret_cast<const char*>(pixels.data), pixels.total() * pixels.elemSize()));
    const auto [first, last] = by_hash.equal_range(hash);
    for (auto it = first; it != last; ++it) {
      const cv::Mat& other = frames[it->second].image;
      if (other.size() == image.size() && other.type() == image.type() && cv::norm(other, image, cv::NORM_INF) == 0) {
        problems.push_back(frames[i].name + " is the same frame as " + frames[it->second].name +
                           ": it would be learnt twice, and judged by folds that learnt it");
        break;
      }
    }
    by_hash.emplace(hash, i);
  }
}

/// @throw std::invalid_argument when an output (--out, its colour model, --detections-out) is a file in an --images
/// or --annotations folder (a frame or label would be overwritten), or two outputs are one file. --out may be --base:
/// the base is read before it is written over.
void refuseOverwritingInputs(const Options& o) {
  std::vector<std::pair<std::string, std::string>> outputs{{"--out", o.out}, {"--out's colour model", modelPathOf(o.out)}};
  if (!o.detections_out.empty()) outputs.emplace_back("--detections-out", o.detections_out);
  std::vector<std::string> folders = o.images;
  folders.insert(folders.end(), o.annotations.begin(), o.annotations.end());
  std::error_code error;
  for (const auto& [option, path] : outputs) {
    for (const std::string& folder : folders) {
      for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
        if (std::filesystem::equivalent(entry.path(), path, error)) {
          throw std::invalid_argument(option + " " + path + " is a file learnt from (in " + folder +
                                      "): it would be overwritten");
        }
      }
    }
  }
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (std::filesystem::weakly_canonical(outputs[i].second, error) ==
          std::filesystem::weakly_canonical(outputs[j].second, error)) {
        throw std::invalid_argument(outputs[i].first + " " + outputs[i].second + " is also " + outputs[j].first);
      }
    }
  }
}

/// Every frame of every folder pair; every problem (unreadable image or XML, missing annotation, annotation without
/// image, two images of one name, and then the labels of the frames that were read: labelProblems) listed.
std::vector<LabelledFrame> readFrames(const Options& o) {
  std::vector<LabelledFrame> frames;
  std::vector<std::string> problems;
  for (std::size_t d = 0; d < o.images.size(); ++d) {
    std::map<std::string, std::string> image_of_stem;  // one frame per annotation: 001.png and 001.jpg are one frame
    const std::vector<std::string> names = imagesIn(o.images[d]);  // sorted: the frames' order, which deals the folds
    for (const std::string& name : names) {
      const std::string stem = name.substr(0, name.find_last_of('.'));
      if (const auto [at, added] = image_of_stem.emplace(stem, name); !added) {
        problems.push_back(o.images[d] + "/" + name + " and " + at->second + " share the annotation " + stem +
                           ".xml: one frame would be learnt twice (keep one of them)");
      }
    }
    for (const std::string& xml : annotationsIn(o.annotations[d])) {
      if (!image_of_stem.count(xml.substr(0, xml.size() - 4))) {
        problems.push_back(o.annotations[d] + "/" + xml + ": no image of that name (.jpg, .jpeg, .png, .bmp) in " +
                           o.images[d]);
      }
    }
    for (const std::string& name : names) {
      const std::string stem = name.substr(0, name.find_last_of('.'));
      if (image_of_stem.at(stem) != name) continue;  // the second image of one frame (named above)
      LabelledFrame f;
      f.name = o.images[d] + "/" + name;
      try {
        f.image = readImageFile(f.name);  // strict: a truncated frame would teach its grey fill
      } catch (const std::invalid_argument& e) {
        problems.push_back(e.what());
        continue;
      }
      if (isGreyImage(f.image)) {
        problems.push_back(f.name + ": a grey image (its three channels equal) cannot teach colours");
        continue;
      }
      const std::string xml = o.annotations[d] + "/" + stem + ".xml";
      try {
        f.labels = readVocLabels(xml, &f.declared_size);
      } catch (const std::invalid_argument& e) {
        problems.push_back(e.what());
        continue;
      }
      frames.push_back(std::move(f));
    }
  }
  refuseRepeatedFrames(frames, problems);
  if (frames.empty() && problems.empty()) problems.push_back("no images found in the --images folders");
  if (!problems.empty()) {  // the frames read have their labels checked too (not yet which colours lack examples)
    const std::vector<std::string> labels = labelProblems(frames, o.learning, false);
    problems.insert(problems.end(), labels.begin(), labels.end());
    throw std::runtime_error(joinProblems("cannot learn from these frames", problems));
  }
  return frames;
}

void printScore(const LearningScore& s, const LearningOptions& options, const std::string& heading) {
  std::printf("\n%s\n\n| colour | labelled | found | recall %% |\n|---|---|---|---|\n", heading.c_str());
  for (std::size_t k = 0; k < options.colours.size(); ++k) {
    std::printf("| %s | %d | %d | %.1f |\n", options.colours[k].c_str(), s.labelled[k], s.found[k],
                s.labelled[k] ? 100.0 * s.found[k] / s.labelled[k] : 0.0);
  }
  const int labelled = std::accumulate(s.labelled.begin(), s.labelled.end(), 0);
  const int found = std::accumulate(s.found.begin(), s.found.end(), 0);
  std::printf("| **all** | %d | %d | %.1f |\n\nunlabelled or false detections: %d in %d frames (%.2f per frame;",
              labelled, found, 100.0 * s.recall(), s.false_detections, s.frames,
              s.frames ? double(s.false_detections) / s.frames : 0.0);
  for (std::size_t k = 0; k < options.colours.size(); ++k) {
    std::printf("%s %s %d", k ? "," : "", options.colours[k].c_str(), s.false_by_colour[k]);
  }
  std::printf(")\n");
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

/// Where each held-out miss was lost: a table of causes by fold and colour, then every miss.
void printMisses(const std::vector<std::pair<int, Miss>>& misses, int folds, const LearningOptions& options) {
  const std::size_t n = options.colours.size();
  std::printf("\nwhere the held-out labels were lost (at the chosen thresholds), by fold and by colour\n\n| cause |");
  for (int k = 0; k < folds; ++k) std::printf(" fold %d |", k + 1);
  for (const auto& c : options.colours) std::printf(" %s |", c.c_str());
  std::printf(" all |\n|---|");
  for (std::size_t k = 0; k < static_cast<std::size_t>(folds) + n + 1; ++k) std::printf("---|");
  std::printf("\n");
  for (int cause = 0; cause < kMissCauseCount; ++cause) {
    std::vector<int> by_fold(static_cast<std::size_t>(folds), 0), by_colour(n, 0);
    for (const auto& [fold, m] : misses) {
      if (static_cast<int>(m.why.cause) != cause) continue;
      ++by_fold[static_cast<std::size_t>(fold)];
      ++by_colour[static_cast<std::size_t>(m.colour)];
    }
    std::printf("| %s |", missCauseName(static_cast<MissCause>(cause)).c_str());
    for (int v : by_fold) std::printf(" %d |", v);
    for (int v : by_colour) std::printf(" %d |", v);
    std::printf(" %d |\n", std::accumulate(by_colour.begin(), by_colour.end(), 0));
  }
  std::printf("\n");
  for (const auto& [fold, m] : misses) {
    std::printf("fold %d: %s %s [%d, %d, %dx%d]: %s (its colour's best votes %.2f)\n", fold + 1, m.frame.c_str(),
                options.colours[m.colour].c_str(), m.label.box.x, m.label.box.y, m.label.box.width, m.label.box.height,
                missCauseName(m.why.cause).c_str(), m.why.best_confidence);
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
  std::printf(" all | false per frame |");
  for (const auto& c : options.colours) std::printf(" false %s |", c.c_str());
  std::printf("\n|---|");
  for (std::size_t k = 0; k < 2 * options.colours.size() + 2; ++k) std::printf("---|");
  std::printf("\n");
  for (std::size_t t = 0; t < thresholds.size(); ++t) {
    const LearningScore& s = totals[t];
    std::printf("| %.2f |", thresholds[t]);
    for (std::size_t k = 0; k < options.colours.size(); ++k) {
      std::printf(" %.1f |", s.labelled[k] ? 100.0 * s.found[k] / s.labelled[k] : 0.0);
    }
    std::printf(" %.1f | %.2f |", 100.0 * s.recall(), s.frames ? double(s.false_detections) / s.frames : 0.0);
    for (int f : s.false_by_colour) std::printf(" %d |", f);
    std::printf("\n");
  }
}

/// `indices` shuffled by `seed` and dealt into `folds` folds (by frame).
std::vector<std::vector<std::size_t>> foldsOf(const std::vector<std::size_t>& indices, int folds, unsigned seed) {
  std::vector<std::size_t> fold(indices.size());
  std::iota(fold.begin(), fold.end(), 0);
  std::mt19937 rng(seed);
  std::shuffle(fold.begin(), fold.end(), rng);
  std::vector<std::vector<std::size_t>> out(static_cast<std::size_t>(folds));
  for (std::size_t i = 0; i < indices.size(); ++i) out[fold[i] % out.size()].push_back(indices[i]);
  return out;
}

std::string thresholdsText(const std::vector<double>& t, const LearningOptions& options) {
  std::string out;
  for (std::size_t k = 0; k < t.size(); ++k) out += (k ? ", " : "") + options.colours[k] + " " + formatted(t[k]);
  return out;
}

/// `x` in the fewest digits that read back as x.
std::string shortest(double x) {
  char text[32];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, x);
    if (std::stod(text) == x) break;
  }
  return text;
}

/// Held-out detections counted at `min_confidence` (per colour) as detect_files' JSON lines, for scripts/evaluate_transdec --detections; nothing when `out` is not open.
/// Each frame's quality report is assessed with `quality` (the base's) on the whole frame (detect_files assesses the
/// frame it searches, scaled: the figures agree within a fraction of a level).
void writeDetections(const std::vector<LabelledFrame>& frames, const std::vector<std::vector<Detection>>& detections,
                     const std::vector<double>& min_confidence, const LearningOptions& options,
                     const QualityConfig& quality, std::ofstream& out) {
  if (!out.is_open()) return;
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const QualityReport report = assessQuality(frames[f].image, quality);
    int id = 0;
    for (const Detection& d : detections[f]) {
      const auto it = std::find(options.colours.begin(), options.colours.end(), d.colour);
      if (it == options.colours.end() || d.confidence < min_confidence[it - options.colours.begin()]) continue;
      out << detectionJson(frames[f].name, id++, d, report, false) << "\n";
    }
  }
  if (!out) throw std::runtime_error("--detections-out: cannot be written");
}

/// The base configuration `root` (as read from `base_path` and validated before learning; the file is not read again)
/// with the learnt colours and model, as YAML. The base's shape model stays the one it names, by absolute path (the
/// written file may lie in another folder).
void writeConfig(YAML::Node root, const std::string& base_path, const std::string& out, const std::string& model_name,
                 const LearningOptions& options, double min_confidence, const std::vector<double>& per_colour) {
  if (YAML::Node shape = root["shape"]; shape && shape.IsMap() && shape["model_file"]) {
    const std::filesystem::path file = shape["model_file"].as<std::string>();
    if (file.is_relative()) {
      shape["model_file"] = (std::filesystem::absolute(base_path).parent_path() / file).lexically_normal().string();
    }
  }
  YAML::Node colours(YAML::NodeType::Sequence);
  for (std::size_t k = 0; k < options.colours.size(); ++k) {
    const std::string& name = options.colours[k];
    // A colour the base does not list is written by its name alone (the learnt model describes it).
    YAML::Node entry(YAML::NodeType::Map);
    entry["name"] = name;
    for (const auto& c : root["colours"]) {
      if (c["name"] && c["name"].as<std::string>() == name) entry = YAML::Clone(c);
    }
    // A threshold of the base's belongs to the base's model: the new one's are chosen here or none.
    entry.remove("min_confidence");
    // Thresholds as written on the command line (0.35, not 0.34999999999999998).
    if (!per_colour.empty()) entry["min_confidence"] = shortest(per_colour[k]);
    entry.SetStyle(YAML::EmitterStyle::Flow);
    colours.push_back(entry);
  }
  root["colours"] = colours;
  root["candidates"]["source"] = "learned";
  root["colour_model"]["file"] = model_name;
  for (const char* key : {"check_file", "check_min_confidence", "check_from_confidence"}) {
    root["colour_model"].remove(key);  // the base's check reads the base's colour model's votes (see main)
  }
  if (min_confidence > 0) root["colour_model"]["min_confidence"] = shortest(min_confidence);
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
  YAML::Node base_yaml;  // the base as read: what is written besides the learnt colours
  try {
    o = parse(argc, argv);
    if (o.base.empty()) o.base = std::string(UWS_SOURCE_DIR) + "/config/detector.yaml";
    // The base's colour model and check are replaced, never read: a base whose model files are missing serves.
    bool base_has_check = false;
    base = loadDetectorConfigFile(o.base, [&](YAML::Node& root) {
      base_yaml = YAML::Clone(root);
      if (!root.IsMap() || !root["colour_model"] || !root["colour_model"].IsMap()) return;
      YAML::Node model = root["colour_model"];
      base_has_check = model["check_file"].IsDefined();
      model.remove("file");
      model.remove("check_file");
      if (root["candidates"] && root["candidates"].IsMap()) root["candidates"]["source"] = "colour_mask";
    });
    if (base_has_check) {  // it reads the base's colour model's votes (learnedConfig leaves it out)
      std::fprintf(stderr, "learn_colours: the base's colour_model.check_file is neither used nor written (learn_checks "
                   "learns a check for the new colour model)\n");
    }
    if (!o.colours_given) {
      for (const ColourClass& c : base.colours.classes) o.learning.colours.push_back(c.name);
    }
    const auto problems = o.learning.validate();
    if (!problems.empty()) throw std::invalid_argument(joinProblems("invalid options", problems));
    refuseOverwritingInputs(o);
  } catch (const std::exception& e) {
    std::cerr << "learn_colours: " << e.what() << "\n" << kUsage;
    return 2;
  }
  try {
    const std::vector<LabelledFrame> frames = readFrames(o);
    if (o.folds > static_cast<int>(frames.size())) {
      throw std::invalid_argument("--folds " + std::to_string(o.folds) + " needs at least as many frames; " +
                                  std::to_string(frames.size()) + " were read");
    }
    checkLabels(frames, o.learning);
    // Proposals are the detector's own, with the base's search settings.
    const Detector proposer(proposerConfig(base));
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
    auto configWith = [&](const ColourModel& m, double confidence, const std::vector<double>& per_colour) {
      DetectorConfig c = learnedConfig(base, o.out, std::make_shared<const ColourModel>(m), o.learning);
      c.learned.min_confidence = confidence;
      for (std::size_t k = 0; k < per_colour.size(); ++k) c.colours.classes[k].min_confidence = per_colour[k];
      return c;
    };
    auto samplesOfFrames = [&](const std::vector<std::size_t>& indices) {
      std::vector<const FrameSamples*> out;
      for (std::size_t i : indices) out.push_back(&samples[i]);
      return out;
    };
    auto framesOf = [&](const std::vector<std::size_t>& indices) {
      std::vector<LabelledFrame> out;
      for (std::size_t i : indices) out.push_back(frames[i]);
      return out;
    };
    // The model learnt from `indices` (frames); `what` names them when a colour or the background has no sample there.
    auto learnOn = [&](const std::vector<std::size_t>& indices, const std::string& what) {
      try {
        return learnColourModel(samplesOfFrames(indices), o.learning);
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(what + " (" + std::to_string(indices.size()) + " frames): " + e.what() +
                                    " (label more frames" +
                                    (indices.size() < frames.size() ? ", or give fewer --folds)" : ")"));
      }
    };
    // Per-colour thresholds chosen by cross-validation within `indices` (frames) alone: each of its folds
    // detected by a model learnt from the others at the grid's lowest threshold, the combination chosen on all.
    auto chooseWithin = [&](const std::vector<std::size_t>& indices, unsigned seed) {
      const std::vector<std::vector<std::size_t>> parts = foldsOf(indices, o.folds, seed);
      std::vector<LabelledFrame> ordered;
      std::vector<std::vector<Detection>> detections;
      for (std::size_t k = 0; k < parts.size(); ++k) {
        std::vector<std::size_t> train;
        for (std::size_t j = 0; j < parts.size(); ++j) {
          if (j != k) train.insert(train.end(), parts[j].begin(), parts[j].end());
        }
        const Detector d(configWith(learnOn(train, "the training frames of inner fold " + std::to_string(k + 1) + " of " +
                                                       std::to_string(o.folds) + " (choosing thresholds)"),
                                    o.choose.front(), {}));
        const std::vector<LabelledFrame> held_out = framesOf(parts[k]);
        const auto found = detectionsOf(d, held_out);
        ordered.insert(ordered.end(), held_out.begin(), held_out.end());
        detections.insert(detections.end(), found.begin(), found.end());
      }
      return chooseThresholds(ordered, detections, o.learning, o.choose, o.max_false);
    };
    std::vector<std::size_t> everything(frames.size());
    std::iota(everything.begin(), everything.end(), 0);
    const unsigned seed = static_cast<unsigned>(o.learning.training.seed);
    if (o.folds > 1) {
      // One detection pass per fold at the lowest threshold asked for, scored at each (scoreAt).
      std::vector<double> thresholds = o.sweep;
      thresholds.push_back(min_confidence);
      std::sort(thresholds.begin(), thresholds.end());
      thresholds.erase(std::unique(thresholds.begin(), thresholds.end()), thresholds.end());
      const std::vector<std::vector<std::size_t>> parts = foldsOf(everything, o.folds, seed);
      std::vector<LearningScore> totals(thresholds.size());
      LearningScore chosen_total;
      std::vector<std::pair<int, Miss>> misses;  // the held-out misses at the chosen thresholds, with their fold
      std::ofstream held_out_detections;
      if (!o.detections_out.empty()) {
        held_out_detections.open(o.detections_out);
        if (!held_out_detections) throw std::runtime_error("--detections-out " + o.detections_out + ": cannot be written");
      }
      for (std::size_t k = 0; k < parts.size(); ++k) {
        std::vector<std::size_t> train;
        for (std::size_t j = 0; j < parts.size(); ++j) {
          if (j != k) train.insert(train.end(), parts[j].begin(), parts[j].end());
        }
        const ColourModel model =
            learnOn(train, "the training frames of fold " + std::to_string(k + 1) + " of " + std::to_string(o.folds));
        const std::vector<LabelledFrame> held_out = framesOf(parts[k]);
        if (!o.choose.empty()) {
          // Thresholds from the training folds only (inner cross-validation), judged on the held-out fold.
          const ThresholdChoice choice = chooseWithin(train, seed * 31U + static_cast<unsigned>(k) + 1U);
          std::printf("fold %zu: min_confidence %s chosen on its training frames\n", k + 1,
                      thresholdsText(choice.min_confidence, o.learning).c_str());
          const Detector chosen(configWith(model, o.choose.front(), choice.min_confidence));
          const auto found = detectionsOf(chosen, held_out);
          chosen_total.add(scoreDetections(held_out, found, o.learning, choice.min_confidence));
          for (Miss& m : explainMisses(chosen, held_out, found, o.learning, choice.min_confidence)) {
            misses.push_back({static_cast<int>(k), std::move(m)});
          }
          writeDetections(held_out, found, choice.min_confidence, o.learning, base.quality, held_out_detections);
        }
        if (!o.choose.empty() && o.sweep.empty()) continue;  // no single threshold to score
        const Detector fold_detector(configWith(model, thresholds.front(), {}));
        const auto found = detectionsOf(fold_detector, held_out);
        for (std::size_t t = 0; t < thresholds.size(); ++t) {
          totals[t].add(scoreDetections(held_out, found, o.learning, std::vector<double>(o.learning.colours.size(), thresholds[t])));
        }
        if (o.choose.empty()) {
          writeDetections(held_out, found, std::vector<double>(o.learning.colours.size(), min_confidence), o.learning,
                          base.quality, held_out_detections);
        }
      }
      const std::string heading = std::to_string(o.folds) + "-fold cross-validation by frame (" +
                                  std::to_string(frames.size()) + " frames; labels under " +
                                  std::to_string(o.learning.min_label_px) + " px tall not counted; ";
      const std::size_t chosen = std::find(thresholds.begin(), thresholds.end(), min_confidence) - thresholds.begin();
      // With thresholds chosen per colour the base's single one means nothing: only those are scored.
      if (o.choose.empty()) printScore(totals[chosen], o.learning, heading + "min_confidence " + formatted(min_confidence) + ")");
      if (!o.sweep.empty()) printSweep(thresholds, totals, o.learning);
      if (!o.choose.empty()) {
        printScore(chosen_total, o.learning,
                   heading + "per-colour min_confidence chosen in each fold by cross-validation on its training frames)");
        printMisses(misses, o.folds, o.learning);
      }
    }
    std::vector<double> per_colour;
    if (!o.choose.empty()) {
      const ThresholdChoice choice = chooseWithin(everything, seed * 31U);
      per_colour = choice.min_confidence;
      std::printf("\nmin_confidence per colour chosen by %d-fold cross-validation on all frames: %s\n", o.folds,
                  thresholdsText(per_colour, o.learning).c_str());
    }
    const ColourModel model = learnOn(everything, "all frames");
    const std::string model_path = modelPathOf(o.out);
    model.save(model_path);
    writeConfig(base_yaml, o.base, o.out, model_path.substr(model_path.find_last_of('/') + 1), o.learning,
                o.choose.empty() ? o.min_confidence : o.choose.front(), per_colour);
    loadDetectorConfigFile(o.out);  // what was written must load
    std::printf("\nwrote %s and %s\n", o.out.c_str(), model_path.c_str());
    if (!tools::standardOutputWritten()) {  // the files are written; what was printed is lost
      std::fprintf(stderr, "learn_colours: what it printed could not be written to standard output (disk full?); %s "
                   "and %s were written\n", o.out.c_str(), model_path.c_str());
      return 1;
    }
  } catch (const std::exception& e) {
    std::cerr << "learn_colours: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
