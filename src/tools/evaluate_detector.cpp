// SPDX-License-Identifier: BSD-3-Clause
// evaluate_detector: renders simulated scenes (scene files, or scenes sampled from seeds), runs the detector on
// every pair and compares the detections with the ground truth. Prints Markdown tables (recall, colour and shape
// right, false detections per frame, range/position/size errors), overall and broken down.
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "brightness_sweep.h"
#include "random_evaluation.h"
#include "sampler_options.h"
#include "scene_files.h"
#include "tool_helpers.h"
#include <yaml-cpp/yaml.h>

#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/sim/renderer.h"
#include "underwater_stereo/sim/scene_sampler.h"

namespace {

using namespace underwater_stereo;

const char* kUsage =
    "usage: evaluate_detector --config detector.yaml [--frames N] [--rate HZ] [--verbose] SCENE.yaml...\n"
    "       evaluate_detector --config detector.yaml --random N [--seed S] [--jobs J] [--size WxH] [--luma LO,HI]\n"
    "                         [--focal-mm LO,HI] [--baseline-m LO,HI]\n"
    "                         [--json FILE] [--worst K DIR] [--shape-rules] [--without-check] [--swapped]\n"
    "       evaluate_detector --config detector.yaml --paper-brightness [--seed S] [--scenes N] [--levels L,L,..]\n"
    "                         [--size WxH]\n"
    "  Scene files: renders frames 0..N-1 of each scene (default 10 at 2 Hz), detects, compares with ground truth.\n"
    "  --random N: pair i (0..N-1) is the scene sampled from seed S+i (default S = 1000), rendered once;\n"
    "    prints recall, colour and shape right, range and position errors and false detections per frame,\n"
    "    overall and by range, turbidity, water, brightness, colour and shape; --jobs J pairs at once;\n"
    "    --json FILE: every object (with the shape features of its detection: what learn_shapes learns from)\n"
    "    and false detection; --worst K DIR: the K worst failures' left images; --shape-rules: shapes by the\n"
    "    hand-made rules, the config's shape.model_file not read (the records a new shape model learns from,\n"
    "    also when the shape features changed and the old model is refused); --without-check: every detection\n"
    "    the colour model passes from colour_model.check_from_confidence on, the config's check_file not read\n"
    "    (the records learn_checks learns from: each detection with its check features); --swapped: each pair\n"
    "    given the wrong way round (the right image as the left): what a head wired swapped reports (its\n"
    "    detections lie in the right image and are matched to the left one's truth: count them, found and false\n"
    "    together; the pairs taken for swapped are counted at the end); --luma LO,HI: every scene exposed to a\n"
    "    mean luma drawn from [LO, HI] instead of the sampler's 30-200 (e.g. 12,40: dark water); --focal-mm LO,HI\n"
    "    and --baseline-m LO,HI: each scene's lens focal length (in air) and baseline drawn from these instead of\n"
    "    the head's 8 mm and 0.12 m (other optics; each pair then gets its own head and calibrated detector).\n"
    "  --paper-brightness: the scene of seed S at the paper's eight brightness levels (mean luma 242.8 .. 18);\n"
    "    --levels L,L,..: at these mean lumas instead (each in (0, 255)); --scenes N: the scenes of seeds\n"
    "    S..S+N-1, each in its table, then recall and false detections per level over the frames that reached it\n"
    "    (within 1).\n"
    "  Objects count when 0.5-5 m away with >= 400 visible pixels and a designated colour.\n"
    "  Exit status 2 on bad options, configuration or scene files (each problem named, nothing rendered); 1 when\n"
    "  a pair failed (--random: each named on stderr, the others still summed and written), or the tables could not\n"
    "  be written to standard output (disk full).\n";

struct Stats {
  int frames = 0, eligible = 0, found = 0, false_detections = 0, shape_eligible = 0, shape_correct = 0;
  std::vector<double> range_err, position_err, size_err_near;  // relative
  std::vector<double> ms;
};

/// Relative size error of `d` against the truth `gt` of shape `shape`.
double sizeError(const sim::GroundTruthObject& gt, ShapeKind shape, const Detection& d) {
  auto rel = [](double a, double b) { return std::abs(a - b) / b; };
  if (shape == ShapeKind::kSphere) return rel(d.size_m.x(), gt.size_m.x());
  if (shape == ShapeKind::kCylinder) return std::max(rel(d.size_m.x(), gt.size_m.x()), rel(d.size_m.z(), gt.size_m.z()));
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
    const ShapeKind shape = shapeFromName(gt.shape, "ground truth of " + gt.name + ": shape");
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
    if (gt.range_m <= 3.0) s.size_err_near.push_back(sizeError(gt, shape, d));
    if (gt.visible_pixels >= 1500) {
      ++s.shape_eligible;
      s.shape_correct += d.shape == shape;
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
  using tools::percentileCell;
  using tools::ratioCell;
  std::cout << "| " << name << " | " << s.frames << " | " << s.eligible << " | " << ratioCell(s.found, s.eligible, 100, 1)
            << " | " << ratioCell(s.false_detections, s.frames, 1, 2) << " | " << percentileCell(s.range_err, 0.5, 100, 2)
            << " | " << percentileCell(s.range_err, 0.95, 100, 2) << " | " << percentileCell(s.position_err, 0.95, 100, 2)
            << " | " << percentileCell(s.size_err_near, 0.5, 100, 2) << " | "
            << ratioCell(s.shape_correct, s.shape_eligible, 100, 1) << " | " << percentileCell(s.ms, 0.5, 1, 1) << " |\n";
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

int evaluateSceneFiles(const DetectorConfig& config, const std::vector<std::pair<std::string, sim::Scene>>& scenes,
                       int frames, double rate) {
  std::vector<std::string> designated;
  for (const auto& c : config.colours.classes) designated.push_back(c.name);
  // Objects of a colour the configuration does not designate count as distractors: named, so that a misspelt colour
  // ("rde") is seen as one, not as a red buoy the detector should have found.
  for (const auto& [path, scene] : scenes) {
    std::string others;
    for (const sim::SceneObject& o : scene.objects) {
      if (std::find(designated.begin(), designated.end(), o.colour) == designated.end()) {
        others += (others.empty() ? "" : ", ") + o.name + " (" + o.colour + ")";
      }
    }
    if (!others.empty()) {
      std::cerr << "evaluate_detector: " << path << ": counted as distractors, their colours not designated here: "
                << others << "\n";
    }
  }
  Stats all;
  std::cout << "| scene | frames | objects | recall % | false/frame | range err median % | range err p95 % |"
               " position err p95 % | size err median % (<= 3 m) | shape correct % | detector ms (median) |\n"
               "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& [path, scene] : scenes) {
    const sim::Renderer renderer(scene);
    Detector detector(config, renderer.calibration());
    Stats s;
    for (int k = 0; k < frames; ++k) {
      const sim::RenderedPair pair = renderer.render(k / rate, static_cast<std::uint64_t>(k));
      accumulate(s, pair.ground_truth,
                 detector.detect(RawFrame(pair.left, pixelLayoutOf(pair.encoding)),
                                 RawFrame(pair.right, pixelLayoutOf(pair.encoding))),
                 designated);
    }
    std::string name = path.substr(path.find_last_of('/') + 1);
    printRow(name, s);
    merge(all, s);
  }
  printRow("**all**", all);
  return 0;
}

struct RandomOptions {
  int pairs = 0;
  std::uint64_t seed = 1000;
  int jobs = 1;
  std::string json_path, worst_dir;
  std::size_t worst = 0;
  bool swapped = false;  ///< each pair given the wrong way round
};

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// Pair `seed` sampled, rendered and detected; also hands back the rendered pair and result when asked.
tools::PairRecord runPair(const sim::SceneSamplerConfig& sampler, const sim::Renderer& head, const Detector& detector,
                          std::uint64_t seed, bool swapped, cv::Mat* left_bgr = nullptr,
                          DetectionResult* result_out = nullptr) {
  const auto started = std::chrono::steady_clock::now();
  const sim::SampledScene sampled = sim::sampleScene(seed, sampler);
  // A scene of its own optics gets its own head, and a detector calibrated for it.
  const sim::Renderer scene_head = tools::SamplerOptions::headFor(sampler, head, sampled.scene);
  std::optional<Detector> own_detector;
  if (sampler.variesOptics()) own_detector.emplace(detector.config(), scene_head.calibration());
  const sim::RenderedPair pair = scene_head.render(0.0, 0);
  const double render_ms = msSince(started);
  const RawFrame left(pair.left, pixelLayoutOf(pair.encoding)), right(pair.right, pixelLayoutOf(pair.encoding));
  const Detector& used = own_detector ? *own_detector : detector;
  const DetectionResult result = swapped ? used.detect(right, left) : used.detect(left, right);
  const cv::Mat bgr = left.bgr();
  tools::PairRecord record = tools::evaluatePair(sampled, pair, result, sim::meanLuma(bgr));
  record.render_ms = render_ms;
  if (left_bgr) *left_bgr = bgr;
  if (result_out) *result_out = result;
  return record;
}

int evaluateRandom(const DetectorConfig& config, const std::string& config_path, const sim::SceneSamplerConfig& sampler,
                   const RandomOptions& opt) {
  const auto started = std::chrono::steady_clock::now();
  std::ofstream json;  // opened first: a bad path fails before the long run, not after it
  if (!opt.json_path.empty()) {
    json.open(opt.json_path);
    if (!json) throw std::runtime_error("cannot write " + opt.json_path);
  }
  // One head for every scene: its pixel rays are computed once.
  const sim::Renderer head(sim::sampleScene(opt.seed, sampler).scene);
  const Detector detector(config, head.calibration());
  // A pair that throws (a detector bug) is named at the end; the others are still run, summed and written.
  const tools::PairRuns runs = tools::runPairs(opt.pairs, opt.jobs, [&](int i) {
    tools::PairRecord r = runPair(sampler, head, detector, opt.seed + static_cast<std::uint64_t>(i), opt.swapped);
    if (verbose) std::cerr << "pair " << i << " (seed " << opt.seed + i << ") done\n";
    return r;
  });
  const std::vector<tools::PairRecord>& records = runs.records;
  const double wall_ms = msSince(started);

  std::cout << "Sampled pairs: " << opt.pairs << " (pair i from seed " << opt.seed << " + i, seeds " << opt.seed << "-"
            << opt.seed + opt.pairs - 1 << "), " << sampler.width << "x" << sampler.height;
  if (!runs.failures.empty()) std::cout << "; " << runs.failures.size() << " failed, not counted (named on stderr)";
  std::cout << "\n\n";
  tools::printSummary(std::cout, records);
  std::vector<double> render_ms, detect_ms;
  for (const auto& r : records) {
    render_ms.push_back(r.render_ms);
    detect_ms.push_back(r.detect_ms);
  }
  std::cout << std::fixed << std::setprecision(0) << "\nTime: sampling + rendering median " << tools::percentile(render_ms, 0.5)
            << " ms, detector median " << tools::percentile(detect_ms, 0.5) << " ms per pair; " << wall_ms / opt.pairs
            << " ms per pair wall-clock with " << opt.jobs << " job(s)\n";
  if (json.is_open()) {
    tools::writeJson(json, records, config_path);
    if (!json.flush()) throw std::runtime_error("cannot write " + opt.json_path);
  }
  if (opt.worst > 0) {
    int rank = 0;
    for (const auto& [p, o] : tools::worstFailures(records, opt.worst)) {
      cv::Mat bgr;
      DetectionResult result;
      const tools::PairRecord again = runPair(sampler, head, detector, records[p].seed, opt.swapped, &bgr, &result);
      std::ostringstream name;
      name << opt.worst_dir << "/worst_" << std::setw(3) << std::setfill('0') << ++rank << "_seed" << records[p].seed
           << "_" << records[p].objects[o].name << ".png";
      if (!cv::imwrite(name.str(), tools::failurePicture(bgr, again, again.objects[o], result))) {
        throw std::runtime_error("cannot write " + name.str());
      }
    }
    std::cout << rank << " worst failures written to " << opt.worst_dir << "\n";
  }
  if (!runs.failures.empty()) {
    std::cerr << "evaluate_detector: " << runs.failures.size() << " of " << opt.pairs
              << " pairs failed and are not counted above:\n";
    for (const auto& [i, what] : runs.failures) std::cerr << "  seed " << opt.seed + i << ": " << what << "\n";
    return 1;
  }
  return 0;
}

enum class Mode { kSceneFiles, kRandom, kPaperBrightness };

std::string modeName(Mode m) {
  switch (m) {
    case Mode::kSceneFiles: return "scene files";
    case Mode::kRandom: return "--random";
    case Mode::kPaperBrightness: return "--paper-brightness";
  }
  return "";
}

/// The modes `option` goes with; none for an option of every mode.
std::vector<Mode> modesOf(const std::string& option) {
  using M = Mode;
  static const std::map<std::string, std::vector<Mode>> kModes{
      {"--frames", {M::kSceneFiles}},         {"--rate", {M::kSceneFiles}},
      {"--verbose", {M::kSceneFiles, M::kRandom}},
      {"--seed", {M::kRandom, M::kPaperBrightness}}, {"--size", {M::kRandom, M::kPaperBrightness}},
      {"--jobs", {M::kRandom}},               {"--json", {M::kRandom}},
      {"--worst", {M::kRandom}},              {"--swapped", {M::kRandom}},
      {"--luma", {M::kRandom}},               {"--focal-mm", {M::kRandom}},
      {"--baseline-m", {M::kRandom}},
      {"--scenes", {M::kPaperBrightness}},    {"--levels", {M::kPaperBrightness}}};
  const auto it = kModes.find(option);
  return it == kModes.end() ? std::vector<Mode>{} : it->second;
}

/// The configuration at `path`, without its learnt shape model (`shape_rules`) or its check after stereo
/// (`without_check`) when asked.
DetectorConfig configWithout(const std::string& path, bool shape_rules, bool without_check) {
  return loadDetectorConfigFile(path, [&](YAML::Node& root) {
    if (!root.IsMap()) return;
    if (shape_rules && root["shape"] && root["shape"].IsMap()) root["shape"].remove("model_file");
    if (without_check && root["colour_model"] && root["colour_model"].IsMap()) {
      // Every region a check would judge is reported.
      YAML::Node m = root["colour_model"];
      if (m["check_from_confidence"]) m["min_confidence"] = YAML::Clone(m["check_from_confidence"]);
      else m["min_confidence"] = LearnedColourConfig{}.check_from_confidence;
      m.remove("check_file");
    }
  });
}

}  // namespace

int main(int argc, char** argv) {
  std::string config_path;
  int frames = 10;
  double rate = 2.0;
  bool paper_brightness = false, shape_rules = false, without_check = false;
  int paper_scenes = 0;
  std::vector<double> levels;
  RandomOptions random;
  sim::SceneSamplerConfig sampler;
  std::vector<std::string> scenes;
  tools::OptionsGiven given;  // the options given: none twice, each checked against the mode
  tools::SamplerOptions sampler_given;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a.size() > 2 && a.compare(0, 2, "--") == 0) given.add(a);
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      auto integer = [&](long long lo, long long hi) { return tools::wholeNumberIn(value(), lo, hi, a); };
      if (a == "--help" || a == "-h") {
        std::cout << kUsage;
        return 0;
      }
      if (a == "--verbose") verbose = true;
      else if (a == "--paper-brightness") paper_brightness = true;
      else if (a == "--shape-rules") shape_rules = true;
      else if (a == "--without-check") without_check = true;
      else if (a == "--config") config_path = value();
      else if (a == "--frames") frames = static_cast<int>(integer(1, 1000000));
      else if (a == "--rate") rate = tools::numberIn(value(), 1e-3, 1e3, a);
      else if (a == "--random") random.pairs = static_cast<int>(integer(1, 10000000));
      else if (a == "--seed") random.seed = static_cast<std::uint64_t>(integer(0, 1LL << 62));
      else if (a == "--scenes") paper_scenes = static_cast<int>(integer(1, 100000));
      else if (a == "--levels") levels = tools::parseLevels(value());
      else if (a == "--jobs") random.jobs = static_cast<int>(integer(1, 64));
      else if (a == "--json") random.json_path = value();
      else if (a == "--swapped") random.swapped = true;
      else if (a == "--worst") {
        random.worst = static_cast<std::size_t>(integer(1, 100000));
        random.worst_dir = value();
      } else if (tools::SamplerOptions::takes(a)) {
        const std::string problem = sampler_given.read(a, value(), sampler);
        if (!problem.empty()) throw std::invalid_argument(problem);
      } else if (!a.empty() && a[0] == '-') {
        throw std::invalid_argument("unknown option " + a);
      } else {
        scenes.push_back(a);
      }
    }
    const int modes = (random.pairs > 0) + paper_brightness + !scenes.empty();
    if (config_path.empty()) throw std::invalid_argument("--config is required");
    if (modes != 1) throw std::invalid_argument("give scene files, --random N or --paper-brightness (one of them)");
    // An option of another mode would be ignored: refused instead, naming the mode it goes with.
    const Mode mode = random.pairs > 0 ? Mode::kRandom : paper_brightness ? Mode::kPaperBrightness : Mode::kSceneFiles;
    for (const std::string& option : given.options()) {
      const std::vector<Mode> modes_of = modesOf(option);
      if (modes_of.empty() || std::find(modes_of.begin(), modes_of.end(), mode) != modes_of.end()) continue;
      std::string goes_with;
      for (Mode m : modes_of) goes_with += (goes_with.empty() ? "" : " or ") + modeName(m);
      throw std::invalid_argument(option + " goes with " + goes_with + ", not with " + modeName(mode));
    }
    const std::string problem = sampler_given.problem(sampler);
    if (!problem.empty()) throw std::invalid_argument(problem);
    // Outputs checked before the long run, not after it.
    if (!random.json_path.empty()) tools::checkWritableFile("--json", random.json_path, "the records file to write");
    if (random.worst > 0) {
      std::error_code error;
      std::filesystem::create_directories(random.worst_dir, error);
      if (error || !std::filesystem::is_directory(random.worst_dir, error) || ::access(random.worst_dir.c_str(), W_OK) != 0) {
        throw std::invalid_argument("--worst " + std::to_string(random.worst) + " " + random.worst_dir +
                                    ": not a folder that can be made and written");
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "evaluate_detector: " << e.what() << "\n" << kUsage;
    return 2;
  }
  // The configuration and every scene file are read before anything is rendered: a bad one is named at once.
  DetectorConfig config;
  std::vector<std::pair<std::string, sim::Scene>> scene_files;
  {
    std::vector<std::string> problems;
    bool config_loaded = false;
    try {
      config = configWithout(config_path, shape_rules, without_check);
      config_loaded = true;
    } catch (const std::exception& e) {
      problems.push_back(e.what());
    }
    // The detector must take each rig (image size, baseline) too: a scene the simulator renders but the detector
    // refuses is named now, not after the table's header.
    scene_files = tools::readSceneFiles(scenes, config_loaded ? &config : nullptr, frames, rate, problems);
    if (scenes.empty() && config_loaded) {
      // Each sampled scene is rendered once, at time 0; of varied optics, a scene sampled with the longest lens and
      // baseline is tried (the calibration's limits; its objects placed for that rig).
      sim::SceneSamplerConfig longest = sampler;
      longest.focal_length_mm.first = longest.focal_length_mm.second;
      longest.baseline_m.first = longest.baseline_m.second;
      const std::string problem = tools::sceneProblem(config, sim::sampleScene(random.seed, longest).scene,
                                                      "the sampled scenes (--size, --focal-mm, --baseline-m)", 1, 1.0);
      if (!problem.empty()) problems.push_back(problem);
    }
    if (!problems.empty()) {
      for (const auto& p : problems) std::cerr << "evaluate_detector: " << p << "\n";
      return 2;
    }
  }
  int status = 0;
  try {
    // The records say how shapes were decided and how pairs were given (their "config").
    if (random.pairs > 0) {
      status = evaluateRandom(config,
                              config_path + (shape_rules ? " --shape-rules" : "") +
                                  (without_check ? " --without-check" : "") + (random.swapped ? " --swapped" : "") +
                                  sampler_given.given(),
                              sampler, random);
    } else if (paper_brightness) {
      tools::sweepBrightness(std::cout, config, sampler, random.seed, std::max(paper_scenes, 1),
                             levels.empty() ? tools::kPaperLevels : levels, paper_scenes > 0);
    } else {
      status = evaluateSceneFiles(config, scene_files, frames, rate);
    }
  } catch (const std::exception& e) {
    std::cerr << "evaluate_detector: " << e.what() << "\n";
    return 1;
  }
  // The tables are the result: a full disk must not pass for a finished evaluation.
  if (!tools::standardOutputWritten()) {
    std::cerr << "evaluate_detector: the results could not be written to standard output (disk full?)\n";
    return 1;
  }
  return status;
}
