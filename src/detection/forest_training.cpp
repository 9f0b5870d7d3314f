// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/forest_training.h"

#include <zlib.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <stdexcept>

#include "underwater_stereo/common/whole_file.h"

namespace underwater_stereo {
namespace {

/// What is wrong with the gzip file at `path` ("" when it is whole, or not gzip): OpenCV reads a gzipped model cut
/// short without a word (a tree cut off at its last node, or dropped), so the file is decompressed once to its end,
/// where zlib checks its length and CRC.
std::string gzipProblem(const std::string& path) {
  std::array<unsigned char, 2> magic{};
  std::ifstream in(path, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(magic.data()), 2) || magic[0] != 0x1f || magic[1] != 0x8b) return "";
  gzFile file = gzopen(path.c_str(), "rb");
  if (file == nullptr) return "cannot be opened";
  std::array<char, 1 << 16> buffer;
  int n = 0;
  while ((n = gzread(file, buffer.data(), static_cast<unsigned>(buffer.size()))) > 0) {
  }
  int error = Z_OK;
  std::string problem = gzerror(file, &error);
  if (error == Z_OK && n == 0) problem.clear();
  if (problem.rfind(path + ": ", 0) == 0) problem.erase(0, path.size() + 2);  // zlib names the file; the caller does
  const int closed = gzclose_r(file);
  if (problem.empty() && closed != Z_OK) problem = closed == Z_BUF_ERROR ? "unexpected end of file" : "cannot be read";
  return problem;
}

}  // namespace

std::vector<std::string> ForestTraining::validate() const {
  std::vector<std::string> p;
  if (trees < 1 || trees > 2000) p.push_back("trees must be in [1, 2000]");
  if (max_depth < 1 || max_depth > 30) p.push_back("max_depth must be in [1, 30]");
  if (!(balance >= 0 && balance <= 1)) p.push_back("balance must be in [0, 1]");
  return p;
}

cv::Ptr<cv::ml::RTrees> trainForest(const cv::Mat& samples, const cv::Mat& responses, const cv::Mat& priors,
                                    const ForestTraining& options) {
  cv::theRNG().state = static_cast<std::uint64_t>(options.seed);
  cv::Ptr<cv::ml::RTrees> forest = cv::ml::RTrees::create();
  forest->setMaxDepth(options.max_depth);
  forest->setMinSampleCount(2);
  forest->setPriors(priors);
  forest->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER, options.trees, 0));
  forest->train(cv::ml::TrainData::create(samples, cv::ml::ROW_SAMPLE, responses));
  return forest;
}

cv::FileStorage openModelFile(const std::string& path, const std::string& named) {
  try {
    checkReadable(path);
  } catch (const UnreadableFile& e) {
    throw std::invalid_argument(named + ": " + e.reason());
  }
  if (const std::string problem = gzipProblem(path); !problem.empty()) {
    throw std::invalid_argument(named + ": unreadable (gzip: " + problem + "; cut short or corrupt?)");
  }
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    throw std::invalid_argument(named + ": unreadable (" + e.msg + ")");
  }
  if (!fs.isOpened()) throw std::invalid_argument(named + ": cannot be opened");
  return fs;
}

cv::FileStorage createModelFile(const std::string& path, const std::string& named) {
  // OpenCV takes a digit after ".gz" as the gzip level and leaves it out of the file's name.
  const bool gzipped = path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0;
  cv::FileStorage fs(gzipped ? path + "9" : path, cv::FileStorage::WRITE);
  if (!fs.isOpened()) throw std::runtime_error(named + ": cannot be written");
  return fs;
}

}  // namespace underwater_stereo
