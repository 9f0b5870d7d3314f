// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/detection/forest_training.h"

#include <zlib.h>

#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "underwater_stereo/common/whole_file.h"

namespace underwater_stereo {
namespace {

/// Whether `bytes` from `at` begin a gzip member.
bool gzipAt(const std::string& bytes, std::size_t at) {
  return bytes.size() >= at + 2 && static_cast<unsigned char>(bytes[at]) == 0x1f &&
         static_cast<unsigned char>(bytes[at + 1]) == 0x8b;
}

/// `bytes` of a gzip file inflated by zlib to the end of its last member, where zlib checks each member's length and
/// CRC; anything after the last member is ignored, as gzread does. @throw std::invalid_argument naming zlib's reason
/// when it is cut short or corrupt.
std::string gunzipped(const std::string& bytes) {
  if (bytes.size() > std::numeric_limits<uInt>::max()) throw std::invalid_argument("larger than 4 GiB");
  z_stream z{};
  if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) throw std::runtime_error("zlib cannot start inflating");
  std::string text;
  std::array<char, 1 << 16> buffer;
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = static_cast<uInt>(bytes.size());
  for (;;) {
    z.next_out = reinterpret_cast<Bytef*>(buffer.data());
    z.avail_out = static_cast<uInt>(buffer.size());
    const int status = inflate(&z, Z_NO_FLUSH);
    text.append(buffer.data(), buffer.size() - z.avail_out);
    if (status == Z_STREAM_END) {
      if (!gzipAt(bytes, bytes.size() - z.avail_in)) break;
      inflateReset(&z);  // another member follows (gzip files may be concatenated)
    } else if (status != Z_OK || (z.avail_in == 0 && z.avail_out > 0)) {  // an error, or the input ends in a member
      const std::string why = status == Z_OK || status == Z_BUF_ERROR ? "unexpected end of file"
                              : z.msg != nullptr                      ? z.msg
                                                                      : "inflate error " + std::to_string(status);
      inflateEnd(&z);
      throw std::invalid_argument(why);
    }
  }
  inflateEnd(&z);
  return text;
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
  std::string text;
  try {
    text = readWholeFile(path);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(named + ": cannot be opened (" + std::string(e.what()).substr(path.size() + 2) + ")");
  }
  if (text.empty()) throw std::invalid_argument(named + ": an empty file");
  // OpenCV reads a gzipped model cut short without a word (a tree cut off at its last node, or dropped): it is
  // inflated here, once, to its end, and OpenCV parses the text.
  if (gzipAt(text, 0)) {
    try {
      text = gunzipped(text);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(named + ": unreadable (gzip: " + e.what() + "; cut short or corrupt?)");
    }
  }
  cv::FileStorage fs;
  try {
    fs.open(text, cv::FileStorage::READ | cv::FileStorage::MEMORY);
  } catch (const cv::Exception& e) {
    throw std::invalid_argument(named + ": unreadable (" + e.msg + ")");
  }
  if (!fs.isOpened()) throw std::invalid_argument(named + ": unreadable (not a model file OpenCV can parse)");
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
