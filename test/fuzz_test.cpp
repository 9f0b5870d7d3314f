// SPDX-License-Identifier: BSD-3-Clause
// Deterministic random-input test ("fuzz") over the core's entry points: the detector configuration and
// camera calibration YAML readers, the scene reader, image files, and Detector (2D and stereo) with random
// sizes, pixel layouts, calibrations and configurations. Every case must either work or be refused with
// std::invalid_argument: any other exception, a crash or a sanitizer report fails. Environment:
//   UWS_FUZZ_CASES  cases to run (default 3000)     UWS_FUZZ_SEED  first seed (default 1)
// Each case has its own seed (first seed + case number), printed on failure: rerun one with
// UWS_FUZZ_SEED=<seed> UWS_FUZZ_CASES=1.
#include <gtest/gtest.h>
#include <unistd.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <random>

#include "underwater_stereo/common/calibration_yaml.h"
#include "underwater_stereo/detection/detector.h"
#include "underwater_stereo/detection/image_checks.h"
#include "underwater_stereo/detection/image_file.h"
#include "underwater_stereo/sim/scene.h"

using namespace underwater_stereo;

namespace {

long envOr(const char* name, long fallback) {
  const char* v = std::getenv(name);
  return v ? std::strtol(v, nullptr, 10) : fallback;
}

class Random {
 public:
  explicit Random(std::uint64_t seed) : rng_(seed) {}
  int integer(int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng_); }
  double real(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  bool chance(double p) { return real(0, 1) < p; }
  template <typename T>
  const T& pick(const std::vector<T>& v) { return v[integer(0, static_cast<int>(v.size()) - 1)]; }
  std::mt19937_64& engine() { return rng_; }

  /// A value of any YAML shape, often an extreme one.
  YAML::Node value() {
    switch (integer(0, 9)) {
      case 0: return YAML::Node(pick<double>({0.0, -1.0, 1e300, -1e-300, 1e12, 0.5, 2.0, 255.0, 1e6}));
      case 1: return YAML::Node(pick<long long>({0, -1, 1, 2, 3, 7, 100, 65536, 2147483647LL, 4294967296LL, -2147483648LL}));
      case 2: return YAML::Node(pick<std::string>({".nan", ".inf", "-.inf", "", "red", "plumb_bob", "equidistant",
                                                    "1e999", "0x10", "true", "~", "[", "{a: 1}"}));
      case 3: {
        YAML::Node list(YAML::NodeType::Sequence);
        for (int i = integer(0, 14); i > 0; --i) list.push_back(real(-1e4, 1e4));
        return list;
      }
      case 4: {
        YAML::Node map(YAML::NodeType::Map);
        map["rows"] = integer(-1, 4);
        map["cols"] = integer(-1, 5);
        return map;
      }
      case 5: return YAML::Node(YAML::NodeType::Null);
      case 6: return YAML::Node(real(-1e3, 1e3));
      case 7: return YAML::Node(integer(-10, 2000));
      case 8: return YAML::Node(chance(0.5));
      default: {
        YAML::Node list(YAML::NodeType::Sequence);
        list.push_back(value());
        return list;
      }
    }
  }

 private:
  std::mt19937_64 rng_;
};

/// Every map entry and sequence element under `node`, as (parent, key) places a mutation can change.
void places(YAML::Node node, std::vector<std::pair<YAML::Node, YAML::Node>>& out, int depth = 0) {
  if (depth > 6) return;
  if (node.IsMap()) {
    for (auto it = node.begin(); it != node.end(); ++it) {
      out.emplace_back(node, it->first);
      places(it->second, out, depth + 1);
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) {
      out.emplace_back(node, YAML::Node(static_cast<int>(i)));
      places(node[i], out, depth + 1);
    }
  }
}

/// `doc` with 1-4 random changes: a value replaced, a key removed, an unknown key added, the whole root replaced.
YAML::Node mutate(const YAML::Node& doc, Random& r) {
  YAML::Node out = YAML::Clone(doc);
  for (int m = r.integer(1, 4); m > 0; --m) {
    std::vector<std::pair<YAML::Node, YAML::Node>> where;
    places(out, where);
    if (where.empty() || r.chance(0.03)) return r.value();
    auto [parent, key] = r.pick(where);
    const int what = r.integer(0, 9);
    if (what < 6) {
      if (parent.IsMap()) parent[key.Scalar()] = r.value();
      else parent[key.as<int>()] = r.value();
    } else if (what < 8 && parent.IsMap()) {
      parent.remove(key.Scalar());
    } else if (parent.IsMap()) {
      parent[r.pick<std::string>({"unknown_key", "rows", "data", "name", "hue"})] = r.value();
    }
  }
  return out;
}

/// A plausible stereo calibration of a small image (fast to run on).
StereoCalibration randomCalibration(Random& r) {
  StereoCalibration c;
  const int w = 2 * r.integer(20, 160), h = 2 * r.integer(20, 120);
  const double f = r.real(60, 600), b = r.real(0.02, 0.5);
  for (CameraCalibration* cam : {&c.left, &c.right}) {
    cam->width = w;
    cam->height = h;
    cam->K = cv::Matx33d(f, 0, w / 2.0 + r.real(-5, 5), 0, f, h / 2.0 + r.real(-5, 5), 0, 0, 1);
    cam->distortion_model = r.chance(0.8) ? DistortionModel::kPlumbBob : DistortionModel::kRationalPolynomial;
    const std::size_t n = cam->distortion_model == DistortionModel::kRationalPolynomial ? 8 : r.pick<std::size_t>({0, 4, 5});
    cam->D.clear();
    for (std::size_t i = 0; i < n; ++i) cam->D.push_back(r.real(-0.2, 0.2));
    cv::Vec3d rvec(r.real(-0.02, 0.02), r.real(-0.02, 0.02), r.real(-0.02, 0.02));
    cv::Matx33d rot;
    cv::Rodrigues(rvec, rot);
    cam->R = rot;
    cam->P = cv::Matx34d(f, 0, w / 2.0, 0, 0, f, h / 2.0, 0, 0, 0, 1, 0);
  }
  c.right.P(0, 3) = -f * b;
  return c;
}

/// One field of `c` set to something odd (often invalid).
void spoil(StereoCalibration& c, Random& r) {
  CameraCalibration& cam = r.chance(0.5) ? c.left : c.right;
  const double odd = r.pick<double>({0.0, -1.0, 1e-6, 1e9, 1e12, std::numeric_limits<double>::quiet_NaN(),
                                     std::numeric_limits<double>::infinity(), 25000.0, 40.0, -500.0, 500.0});
  switch (r.integer(0, 8)) {
    case 0: cam.K.val[r.integer(0, 8)] = odd; break;
    case 1: cam.P.val[r.integer(0, 11)] = odd; break;
    case 2: cam.R.val[r.integer(0, 8)] = odd; break;
    case 3: cam.D.assign(r.integer(0, 14), odd); break;
    case 4: cam.width = r.pick<int>({0, 1, -5, 31, 16385, 100000, cam.width + 2}); break;
    case 5: cam.height = r.pick<int>({0, 1, -5, 31, 16385, cam.height + 2}); break;
    case 6: cam.distortion_model = DistortionModel::kRationalPolynomial; break;
    case 7: c.right.P(0, 3) = -c.right.P(0, 0) * r.pick<double>({1e12, 1e-4, -0.1, 3.0, 0.0}); break;
    default: cam.D = {odd, 0, 0, 0, 0};
  }
}

/// A scene of coloured discs on water, the right view shifted by `disparity` px.
std::pair<cv::Mat, cv::Mat> scenePair(cv::Size size, int disparity, Random& r) {
  cv::Mat left(size, CV_8UC3, cv::Scalar(r.integer(60, 140), r.integer(60, 120), r.integer(20, 60)));
  cv::randn(left, cv::Scalar::all(0), cv::Scalar::all(r.integer(0, 12)));
  left += cv::Scalar(r.integer(60, 140), r.integer(60, 120), r.integer(20, 60));
  cv::Mat right = left.clone();
  for (int k = r.integer(0, 3); k > 0; --k) {
    const cv::Point centre(r.integer(0, size.width), r.integer(0, size.height));
    const int radius = r.integer(2, std::max(3, size.width / 3));
    const cv::Scalar colour = r.pick<cv::Scalar>({{30, 30, 200}, {30, 200, 60}, {0, 140, 255}, {0, 220, 220}});
    cv::circle(left, centre, radius, colour, cv::FILLED);
    cv::circle(right, centre - cv::Point(disparity, 0), radius, colour, cv::FILLED);
  }
  return {left, right};
}

/// `image` as a frame of a random layout or a deliberately wrong cv::Mat type.
RawFrame asFrame(const cv::Mat& bgr, int kind) {
  switch (kind) {
    case 0: return RawFrame(bgr);
    case 1: {
      cv::Mat grey;
      cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
      return RawFrame(grey);
    }
    case 2: {  // a Bayer mosaic (RGGB) sampled from the BGR image
      cv::Mat mosaic(bgr.size(), CV_8UC1);
      for (int y = 0; y < bgr.rows; ++y) {
        for (int x = 0; x < bgr.cols; ++x) mosaic.at<uchar>(y, x) = bgr.at<cv::Vec3b>(y, x)[y % 2 == 0 ? (x % 2 == 0 ? 2 : 1) : (x % 2 == 0 ? 1 : 0)];
      }
      return RawFrame(mosaic, PixelLayout::kBayerRggb);
    }
    case 3: {
      cv::Mat other;
      bgr.convertTo(other, CV_16UC3);
      return RawFrame(other);  // refused: not 8-bit
    }
    default: {
      cv::Mat four;
      cv::cvtColor(bgr, four, cv::COLOR_BGR2BGRA);
      return RawFrame(four);  // refused: 4 channels
    }
  }
}

/// The YAML that camera_calibration writes for `c`.
YAML::Node calibrationYaml(const CameraCalibration& c) {
  auto matrix = [](int rows, int cols, const double* data) {
    YAML::Node m;
    m["rows"] = rows;
    m["cols"] = cols;
    for (int i = 0; i < rows * cols; ++i) m["data"].push_back(data[i]);
    return m;
  };
  YAML::Node n;
  n["image_width"] = c.width;
  n["image_height"] = c.height;
  n["camera_name"] = "fuzz";
  n["camera_matrix"] = matrix(3, 3, c.K.val);
  n["distortion_model"] = distortionModelName(c.distortion_model);
  n["distortion_coefficients"] = matrix(1, static_cast<int>(c.D.size()), c.D.data());
  n["rectification_matrix"] = matrix(3, 3, c.R.val);
  n["projection_matrix"] = matrix(3, 4, c.P.val);
  return n;
}

std::string tempPath(const std::string& name) {
  return (testing::TempDir().empty() ? std::string("/tmp/") : testing::TempDir()) + "uws_fuzz_" +
         std::to_string(::getpid()) + "_" + name;
}

const DetectorConfig& defaultConfig() {
  static const DetectorConfig config = loadDetectorConfigFile(std::string(UWS_SOURCE_DIR) + "/config/detector.yaml");
  return config;
}

struct Tally {
  std::map<std::string, int> accepted, refused;
};

/// Runs `body`; std::invalid_argument counts as a refusal (its message must say something), anything else fails.
template <typename Body>
void expectWorksOrRefuses(const std::string& what, Tally& tally, Body body) {
  try {
    body();
    ++tally.accepted[what];
  } catch (const std::invalid_argument& e) {
    EXPECT_GT(std::string(e.what()).size(), 10U) << what << ": a refusal without a reason";
    ++tally.refused[what];
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": " << typeid(e).name() << " escaped: " << e.what();
  }
}

void fuzzDetectorConfig(Random& r, const YAML::Node& defaults, Tally& tally) {
  const YAML::Node doc = mutate(defaults, r);
  SCOPED_TRACE("config:\n" + YAML::Dump(doc));
  expectWorksOrRefuses("detector config", tally, [&] {
    const DetectorConfig config = parseDetectorConfig(doc);
    // A configuration that parses must work: on a small scene, 2D and stereo.
    const StereoCalibration calibration = randomCalibration(r);
    const cv::Size size(calibration.left.width, calibration.left.height);
    const auto [left, right] = scenePair(size, r.integer(0, 30), r);
    const Detector detector(config, calibration);
    if (imageSizeProblem(size.width, size.height, config.search_scale).empty()) {
      detector.detect2d(left);
      detector.detect(left, right);
    }
  });
}

void fuzzCalibrationYaml(Random& r, Tally& tally) {
  const YAML::Node doc = mutate(calibrationYaml(randomCalibration(r).left), r);
  SCOPED_TRACE("calibration:\n" + YAML::Dump(doc));
  expectWorksOrRefuses("calibration yaml", tally, [&] {
    const CameraCalibration c = parseCameraCalibration(doc);
    EXPECT_TRUE(c.validate("read").empty()) << "a calibration read without complaint does not validate";
  });
}

void fuzzScene(Random& r, const YAML::Node& scene, Tally& tally) {
  const YAML::Node doc = mutate(scene, r);
  SCOPED_TRACE("scene:\n" + YAML::Dump(doc));
  expectWorksOrRefuses("scene yaml", tally, [&] { sim::parseScene(doc); });
}

void fuzzImageFile(Random& r, Tally& tally) {
  const cv::Size size(r.integer(1, 300), r.integer(1, 300));
  const cv::Mat image = scenePair(size, 0, r).first;
  const std::string ext = r.pick<std::string>({".jpg", ".png", ".bmp", ".ppm"});
  std::vector<uchar> bytes;
  cv::imencode(ext, image, bytes);
  const int how = r.integer(0, 5);
  bool must_refuse = false;
  if (how == 0 && bytes.size() > 4) {  // truncated: a JPEG or PNG cut short is always refused
    bytes.resize(r.integer(1, static_cast<int>(bytes.size()) - 3));
    must_refuse = ext == ".jpg" || ext == ".png";
  } else if (how == 1) {  // bytes flipped
    for (int k = r.integer(1, 20); k > 0; --k) bytes[r.integer(0, static_cast<int>(bytes.size()) - 1)] ^= r.integer(1, 255);
  } else if (how == 2) {  // garbage appended
    for (int k = r.integer(1, 100); k > 0; --k) bytes.push_back(static_cast<uchar>(r.integer(0, 255)));
  } else if (how == 3) {  // not an image
    bytes.assign(r.integer(0, 600), 0);
    for (auto& b : bytes) b = static_cast<uchar>(r.integer(0, 255));
    must_refuse = true;
  }
  const std::string path = tempPath("image" + ext);
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  SCOPED_TRACE(ext + " of " + std::to_string(size.width) + "x" + std::to_string(size.height) + ", mutation " +
               std::to_string(how) + ", " + std::to_string(bytes.size()) + " bytes");
  const bool small = !imageSizeProblem(size.width, size.height).empty();
  expectWorksOrRefuses("image file", tally, [&] {
    const cv::Mat read = readImageFile(path);
    EXPECT_FALSE(must_refuse) << "a truncated or random file was read";
    EXPECT_TRUE(imageSizeProblem(read.cols, read.rows).empty());
    if (how >= 4) {
      EXPECT_FALSE(small) << "an image below the size limit was read";
    }
    Detector(defaultConfig()).detect2d(read);
  });
  std::remove(path.c_str());
}

void fuzzDetector(Random& r, Tally& tally) {
  DetectorConfig config = defaultConfig();
  config.search_scale = r.pick<double>({0.5, 1.0, 0.25, 0.1, 0.7});
  StereoCalibration calibration = randomCalibration(r);
  if (r.chance(0.3)) spoil(calibration, r);
  cv::Size size(std::clamp(calibration.left.width, 1, 17000), std::clamp(calibration.left.height, 1, 17000));
  if (r.chance(0.25)) size = cv::Size(r.integer(1, 200), r.integer(1, 200));  // any size, tiny ones included
  const auto [left, right] = scenePair(size, r.integer(-5, 40), r);
  const int kind = r.integer(0, 9) < 8 ? r.integer(0, 2) : r.integer(3, 4);
  SCOPED_TRACE("detector on " + std::to_string(size.width) + "x" + std::to_string(size.height) + ", frame kind " +
               std::to_string(kind) + ", search_scale " + std::to_string(config.search_scale));
  expectWorksOrRefuses("detector 2d", tally, [&] { Detector(config).detect2d(asFrame(left, kind)); });
  expectWorksOrRefuses("detector stereo", tally, [&] {
    const Detector detector(config, calibration);
    const DetectionResult result = detector.detect(asFrame(left, kind), asFrame(right, kind));
    for (const Detection& d : result.objects) {
      EXPECT_TRUE(d.position_m.allFinite() && d.size_m.allFinite() && std::isfinite(d.range_m)) << "NaN reported";
    }
  });
}

}  // namespace

TEST(Fuzz, EveryEntryPointWorksOrRefusesWithAReason) {
  const long cases = envOr("UWS_FUZZ_CASES", 3000), first_seed = envOr("UWS_FUZZ_SEED", 1);
  const YAML::Node defaults = YAML::LoadFile(std::string(UWS_SOURCE_DIR) + "/config/detector.yaml");
  const YAML::Node scene = YAML::LoadFile(std::string(UWS_SOURCE_DIR) + "/test/scenes/small_pool.yaml");
  Tally tally;
  for (long k = 0; k < cases; ++k) {
    const std::uint64_t seed = static_cast<std::uint64_t>(first_seed + k);
    SCOPED_TRACE("fuzz case seed " + std::to_string(seed) + " (rerun: UWS_FUZZ_SEED=" + std::to_string(seed) +
                 " UWS_FUZZ_CASES=1)");
    Random r(seed);
    switch (r.integer(0, 9)) {
      case 0: case 1: fuzzDetectorConfig(r, defaults, tally); break;
      case 2: case 3: fuzzCalibrationYaml(r, tally); break;
      case 4: fuzzScene(r, scene, tally); break;
      case 5: case 6: fuzzImageFile(r, tally); break;
      default: fuzzDetector(r, tally);
    }
    if (::testing::Test::HasFailure()) break;  // the first failing seed is the useful one
  }
  std::cout << cases << " cases from seed " << first_seed << ":";
  for (const auto& [what, n] : tally.accepted) std::cout << " " << what << " " << n << " worked,";
  for (const auto& [what, n] : tally.refused) std::cout << " " << what << " " << n << " refused,";
  std::cout << std::endl;
}
