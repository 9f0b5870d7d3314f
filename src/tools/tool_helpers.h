// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Small pieces the command-line tools share.
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "underwater_stereo/common/whole_file.h"
#include "underwater_stereo/config/yaml_fields.h"

namespace underwater_stereo {
namespace tools {

/// `text` as a number into `out`: false (out untouched) unless the whole of it is one, leading blanks allowed; decimal
/// only (strtod would also read hexadecimal: "0x10" as 16).
inline bool parseNumber(const std::string& text, double& out) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end == text.c_str() || *end != '\0' || text.find_first_of("xX") != std::string::npos) return false;
  out = v;
  return true;
}

/// The error for an option value `text` that is not a number (a whole one where `whole`) in [lo, hi].
template <typename Number>
std::invalid_argument notANumberIn(const std::string& text, Number lo, Number hi, bool whole, const std::string& what) {
  std::ostringstream message;
  message << std::setprecision(15) << what << ": '" << text << "' is not " << (whole ? "a whole number" : "a number")
          << " in [" << lo << ", " << hi << "]";
  return std::invalid_argument(message.str());
}

/// `text`, the whole of it, as a number in [lo, hi]. @throw std::invalid_argument starting with `what` otherwise.
inline double numberIn(const std::string& text, double lo, double hi, const std::string& what) {
  double v = NAN;
  if (!parseNumber(text, v) || !(v >= lo && v <= hi)) throw notANumberIn(text, lo, hi, false, what);
  return v;
}

/// `text`, the whole of it, as a whole number in [lo, hi] (read as an integer: large seeds stay exact).
/// @throw std::invalid_argument starting with `what` otherwise.
inline long long wholeNumberIn(const std::string& text, long long lo, long long hi, const std::string& what) {
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text.c_str(), &end, 10);
  if (text.empty() || end == text.c_str() || *end != '\0' || errno != 0 || v < lo || v > hi) {
    throw notANumberIn(text, lo, hi, true, what);
  }
  return v;
}

/// The options a command line gave so far: one that takes a single value, given twice, is refused (the last value
/// would win without a word; `detect_files --list a --list b` dropped a's frames).
class OptionsGiven {
 public:
  /// `repeatable`: the options that may come more than once (each adds a value).
  explicit OptionsGiven(std::vector<std::string> repeatable = {}) : repeatable_(std::move(repeatable)) {}
  /// @throw std::invalid_argument "<option> is given twice" when `option` came before and is not repeatable.
  void add(const std::string& option) {
    if (std::find(given_.begin(), given_.end(), option) == given_.end()) {
      given_.push_back(option);
    } else if (std::find(repeatable_.begin(), repeatable_.end(), option) == repeatable_.end()) {
      throw std::invalid_argument(option + " is given twice (one would silently win over the other)");
    }
  }
  /// Every option given so far, once each, in the order given.
  const std::vector<std::string>& options() const { return given_; }

 private:
  std::vector<std::string> repeatable_, given_;
};

/// `text` as WIDTHxHEIGHT (two whole numbers that fit an int, and nothing else) into `width` and `height`; false
/// (both untouched) otherwise: 4294967936x400 is no size, not 640x400 wrapped around.
inline bool parseImageSize(const std::string& text, int& width, int& height) {
  const char* const end = text.data() + text.size();
  int w = 0, h = 0;
  const auto [after_w, w_error] = std::from_chars(text.data(), end, w);
  if (w_error != std::errc() || after_w == end || *after_w != 'x') return false;
  const auto [after_h, h_error] = std::from_chars(after_w + 1, end, h);
  if (h_error != std::errc() || after_h != end) return false;
  width = w;
  height = h;
  return true;
}

/// "LO,HI" read strictly (two numbers, nothing after them) into `interval`; false (and `interval` untouched) otherwise.
inline bool parseInterval(const std::string& text, std::pair<double, double>& interval) {
  double lo = 0, hi = 0;
  int used = 0;
  if (std::sscanf(text.c_str(), "%lf,%lf%n", &lo, &hi, &used) != 2 || used != static_cast<int>(text.size())) {
    return false;
  }
  interval = {lo, hi};
  return true;
}

/// Whether all a tool printed so far reached its standard output, through iostreams and stdio alike (flushed: a full
/// disk shows only then). A tool whose printed results are lost says so and exits 1 rather than pass for finished.
inline bool standardOutputWritten() {
  std::cout.flush();
  return std::cout && std::fflush(stdout) == 0 && !std::ferror(stdout);
}

/// `value` with `digits` decimals, as a table cell.
inline std::string fixedCell(double value, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << value;
  return s.str();
}

/// `part` / `whole` times `scale` (100: a percentage) with `digits` decimals, as a table cell; "-" when `whole` is 0.
inline std::string ratioCell(double part, int whole, double scale, int digits) {
  return whole <= 0 ? "-" : fixedCell(scale * part / whole, digits);
}

/// The q-quantile (0..1, nearest rank) of `v`; NaN when empty.
inline double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

/// The q-quantile of `v` times `scale` as a table cell of `digits` decimals, "-" when `v` is empty.
inline std::string percentileCell(const std::vector<double>& v, double q, double scale, int digits) {
  return v.empty() ? "-" : fixedCell(scale * percentile(v, q), digits);
}

/// Checks that the file `path` (given as `option`, e.g. "--out") can be written, before a tool spends minutes on
/// what it will write there. @throw std::invalid_argument naming it when it is a folder, its folder is missing or
/// not writable, or it exists and cannot be written; `what` says what to give instead ("the model file to write").
inline void checkWritableFile(const std::string& option, const std::string& path, const std::string& what) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw std::invalid_argument(option + " " + path + " is a folder: give " + what);
  }
  const std::filesystem::path folder = std::filesystem::absolute(path, error).parent_path();
  if (!std::filesystem::is_directory(folder, error) || ::access(folder.c_str(), W_OK) != 0) {
    throw std::invalid_argument(option + " " + path + ": its folder " + folder.string() + " is not a writable folder");
  }
  if (std::filesystem::exists(path, error) && ::access(path.c_str(), W_OK) != 0) {
    throw std::invalid_argument(option + " " + path + " exists and cannot be written");
  }
}

/// @throw std::invalid_argument when two of `paths` (given as `option`) are the same file or folder: its contents
/// would be learnt twice; `why` adds what else that would do.
inline void refuseRepeated(const std::string& option, const std::vector<std::string>& paths, const std::string& why) {
  for (std::size_t i = 0; i < paths.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      std::error_code error;
      if (paths[i] == paths[j] || std::filesystem::equivalent(paths[i], paths[j], error)) {
        throw std::invalid_argument(option + paths[i] + " is given twice (also as " + paths[j] + "): " + why);
      }
    }
  }
}

/// @throw std::invalid_argument when two of the files `paths` hold the same bytes (a copy under another name); `why`
/// adds what learning from both would do. A file that cannot be read is left to its reader to name.
inline void refuseCopies(const std::vector<std::string>& paths, const std::string& why) {
  std::vector<std::uintmax_t> sizes;  // 0 when empty or not a file: never a copy
  std::vector<std::optional<std::string>> contents;  // each file read once, and only when another has its size
  const auto bytesOf = [&](std::size_t i) -> const std::string& {
    if (!contents[i]) {
      try {
        contents[i] = readWholeFile(paths[i]);
      } catch (const UnreadableFile&) {
        contents[i] = std::string();  // never a copy: its reader names why it cannot be read
      }
    }
    return *contents[i];
  };
  for (std::size_t i = 0; i < paths.size(); ++i) {
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(paths[i], error);
    sizes.push_back(error ? 0 : size);
    contents.emplace_back();
    for (std::size_t j = 0; j < i; ++j) {
      if (sizes[i] == 0 || sizes[i] != sizes[j]) continue;
      if (!bytesOf(i).empty() && bytesOf(i) == bytesOf(j)) {
        throw std::invalid_argument(paths[i] + " holds the same records as " + paths[j] + ": " + why);
      }
    }
  }
}

/// The JSON records evaluate_detector --random --json wrote to `path` (what learn_shapes and learn_checks learn from).
/// @throw std::invalid_argument naming the file when it is a folder, not readable, two documents, repeats a key, holds
/// no "pairs" list, a "config" that is no string, or was made with --swapped.
inline YAML::Node loadRandomRecords(const std::string& path) {
  YAML::Node root;
  try {
    const std::vector<YAML::Node> documents = YAML::LoadAll(readWholeFile(path));  // JSON is YAML
    if (documents.size() > 1) {
      throw std::invalid_argument(path + ": " + std::to_string(documents.size()) +
                                  " records documents one after the other (files joined?): give each file on its own");
    }
    if (!documents.empty()) root = documents.front();
  } catch (const UnreadableFile& e) {
    throw std::invalid_argument(path + ": cannot read the records file: " + e.reason() +
                                " (records are what evaluate_detector --random --json FILE writes)");
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(path + ": not readable as JSON (" + e.what() + ")");
  }
  // yaml-cpp keeps the first of two equal keys: a record's second "shape" or "eligible" would be dropped unseen.
  if (const std::vector<std::string> repeated = repeatedKeys(root); !repeated.empty()) {
    throw std::invalid_argument(joinProblems(path + ": keys given twice", repeated));
  }
  if (!root.IsMap() || !root["pairs"] || !root["pairs"].IsSequence()) {
    throw std::invalid_argument(path + ": no \"pairs\" list (not evaluate_detector --random --json records)");
  }
  if (root["config"] && !root["config"].IsScalar()) {
    throw std::invalid_argument(path + ": malformed records (\"config\" is not the command line they were made with)");
  }
  if (root["config"] && root["config"].as<std::string>().find(" --swapped") != std::string::npos) {
    throw std::invalid_argument(path + ": made with --swapped (pairs given the wrong way round): nothing to learn from");
  }
  return root;
}

/// A record's true/false field `key` (absent: false). @throw YAML::Exception (forEachRecordPair names the pair) when
/// it is there but neither true nor false: a "maybe" would otherwise drop the record without a word.
inline bool recordFlag(const YAML::Node& record, const char* key) {
  const YAML::Node value = record[key];
  if (!value) return false;
  bool flag = false;
  if (!value.IsScalar() || !YAML::convert<bool>::decode(value, flag)) {
    throw YAML::Exception(value.Mark(), std::string("\"") + key + "\" is neither true nor false");
  }
  return flag;
}

/// A record's feature `value`: null (what evaluate_detector writes for a feature it could not compute) as 0, as the
/// detector's learnt models read it. @throw YAML::Exception (forEachRecordPair names the pair) on .nan or .inf,
/// which evaluate_detector never writes: a model learnt from them would split on nothing.
inline float recordFeature(const YAML::Node& value) {
  if (value.IsNull()) return 0.0F;
  const float f = value.as<float>();
  if (!std::isfinite(f)) throw YAML::Exception(value.Mark(), "a feature is '" + value.Scalar() + "', not a finite number");
  return f;
}

/// Calls `add` with each pair of the records `root` read from `path`; a field of the wrong kind is named with the file
/// and the pair's seed. @throw std::invalid_argument "PATH: seed S: malformed record (...)", or what `add` throws.
inline void forEachRecordPair(const YAML::Node& root, const std::string& path,
                              const std::function<void(const YAML::Node& pair, const std::string& where)>& add) {
  for (const YAML::Node& pair : root["pairs"]) {
    const std::string where = path + ": seed " + (pair.IsMap() ? pair["seed"].as<std::string>("?") : std::string("?"));
    try {
      if (!pair.IsMap()) throw std::invalid_argument(where + ": malformed record (a pair is not a map)");
      for (const char* list : {"objects", "false_detections"}) {  // iterating a scalar would yield nothing, silently
        if (pair[list] && !pair[list].IsSequence()) {
          throw std::invalid_argument(where + ": malformed record (\"" + list + "\" is not a list)");
        }
      }
      add(pair, where);
    } catch (const YAML::Exception& e) {
      throw std::invalid_argument(where + ": malformed record (" + e.what() + ")");
    }
  }
}

/// `train()`'s model, learnt from what the records files `records` held (`samples` rows of `what`); a trainer's
/// refusal (too few samples, a class with none: its message names neither the files nor the counts) is named with
/// both. @throw std::invalid_argument "A.json, B.json: N what to learn from: <the trainer's message>".
template <typename Train>
auto trainOnRecords(const std::vector<std::string>& records, std::size_t samples, const std::string& what, Train train)
    -> decltype(train()) {
  try {
    return train();
  } catch (const std::invalid_argument& e) {
    std::string files;
    for (const std::string& r : records) files += (files.empty() ? "" : ", ") + r;
    throw std::invalid_argument(files + ": " + std::to_string(samples) + " " + what + " to learn from: " + e.what());
  }
}

/// Reads a learning tool's command line: --help, the options in `values` (each takes one value, e.g. "--out"), and
/// the records files. @return -1 to go on, or the exit code to leave with (0 after --help, 2 after an unknown option
/// or an option without its value), with the usage printed.
inline int parseRecordsCommandLine(int argc, char** argv, const std::string& tool, const char* usage,
                                   std::map<std::string, std::string>& values, std::vector<std::string>& inputs) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") {
      std::cout << usage;
      return 0;
    }
    if (values.count(a) != 0 && i + 1 < argc) {
      if (!values[a].empty()) {
        std::cerr << tool << ": " << a << " is given twice (one would silently win over the other)\n" << usage;
        return 2;
      }
      values[a] = argv[++i];
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << tool << ": unknown option or option without its value: " << a << "\n" << usage;
      return 2;
    } else {
      inputs.push_back(a);
    }
  }
  return -1;
}

/// A learning tool's output file and records files checked before any record is read (checkWritableFile,
/// refuseRepeated, refuseCopies, and the output is none of the records: it would overwrite one): @return -1 to go on,
/// or 2 with the problem and the usage printed.
inline int checkOutputAndRecords(const std::string& tool, const char* usage, const std::string& out,
                                 const std::string& out_what, const std::vector<std::string>& records,
                                 const std::string& learnt_twice) {
  try {
    checkWritableFile("--out", out, out_what);
    refuseRepeated("", records, learnt_twice);
    refuseCopies(records, learnt_twice);
    for (const std::string& r : records) {
      std::error_code error;
      if (r == out || std::filesystem::equivalent(r, out, error)) {
        throw std::invalid_argument("--out " + out + " is also a records file to learn from: it would be overwritten");
      }
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << tool << ": " << e.what() << "\n" << usage;
    return 2;
  }
  return -1;
}

}  // namespace tools
}  // namespace underwater_stereo
