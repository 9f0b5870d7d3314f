// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Reading typed fields out of YAML maps, collecting every problem instead of stopping at the first.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

#include "underwater_stereo/common/whole_file.h"

namespace underwater_stereo {

/// Collects the problems found while reading one YAML document; each names the field's full path.
class YamlFields {
 public:
  explicit YamlFields(std::vector<std::string>& errors) : errors_(errors) {}

  /// Reads `map[key]` into `value` when present; keeps `value` (the default) when absent.
  /// A present value of the wrong type is recorded as a problem and `value` is left unchanged.
  template <typename T>
  void optional(const YAML::Node& map, const std::string& key, const std::string& path, T& value) {
    if (!map.IsMap()) {  // operator[] would throw on a scalar or a list
      notAMap(map, path);
      return;
    }
    const YAML::Node node = map[key];
    if (!node) return;
    try {
      value = node.as<T>();
    } catch (const YAML::Exception&) {
      errors_.push_back(path + key + ": expected " + typeName<T>() + ", got '" + YAML::Dump(node) + "'");
    }
  }

  /// Like optional(), but a missing key is a problem.
  template <typename T>
  void required(const YAML::Node& map, const std::string& key, const std::string& path, T& value) {
    if (!map.IsMap()) {
      notAMap(map, path);
      return;
    }
    if (!map[key]) {
      errors_.push_back(path + key + ": missing");
      return;
    }
    optional(map, key, path, value);
  }

  /// Reads a fixed-length list of numbers (e.g. a 3-vector [x, y, z]).
  void optionalVector(const YAML::Node& map, const std::string& key, const std::string& path,
                      std::vector<double>& value, std::size_t expected_size);
  void optionalVector3(const YAML::Node& map, const std::string& key, const std::string& path,
                       Eigen::Vector3d& value);

  /// Records every key of `map` that is not in `allowed` (catches misspelt parameters).
  void onlyKeys(const YAML::Node& map, const std::string& path, std::initializer_list<const char*> allowed);
  void onlyKeys(const YAML::Node& map, const std::string& path, const std::vector<std::string>& allowed);

  /// Records a problem that is not about one field's type.
  void fail(const std::string& message) { errors_.push_back(message); }

  /// Records once that `node`, at `path`, should have been a map.
  void notAMap(const YAML::Node& node, const std::string& path);

 private:
  template <typename T>
  static const char* typeName();
  std::vector<std::string>& errors_;
};

template <>
inline const char* YamlFields::typeName<double>() { return "a number"; }
template <>
inline const char* YamlFields::typeName<int>() { return "an integer"; }
template <>
inline const char* YamlFields::typeName<unsigned>() { return "a non-negative integer"; }
template <>
inline const char* YamlFields::typeName<bool>() { return "true or false"; }
template <>
inline const char* YamlFields::typeName<std::string>() { return "a string"; }
template <>
inline const char* YamlFields::typeName<std::vector<double>>() { return "a list of numbers"; }

/// Joins problems into one message, one per line, for an exception or a log.
std::string joinProblems(const std::string& heading, const std::vector<std::string>& problems);

/// Every key that a map of `node` (or of a map or list within it) holds twice: yaml-cpp keeps both and a lookup
/// gives the first, so the second value, often the edit, would be ignored without a word. One line each:
/// "key 'a.b' twice (lines 3 and 9)".
std::vector<std::string> repeatedKeys(const YAML::Node& node);

/// Loads the YAML file at `path`, refuses it when a key is repeated (repeatedKeys), and hands its root to
/// `parse`. @throw std::invalid_argument naming the file (and `what` it should hold) when it cannot be read or
/// parsed or repeats a key, or with `parse`'s message prefixed by the path (a yaml-cpp exception that escapes
/// `parse` included).
template <typename Parse>
auto parseYamlFile(const std::string& path, const std::string& what, Parse parse) {
  YAML::Node root;
  try {
    root = YAML::Load(readWholeFile(path));  // not YAML::LoadFile: its BadFile names no reason, a folder a stream error
  } catch (const UnreadableFile& e) {
    throw std::invalid_argument("cannot read " + what + " '" + path + "': " + e.reason());
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument("cannot read " + what + " '" + path + "': " + e.what());
  }
  const std::vector<std::string> repeated = repeatedKeys(root);
  if (!repeated.empty()) throw std::invalid_argument(joinProblems(path + ": keys given twice", repeated));
  try {
    return parse(root);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  } catch (const YAML::Exception& e) {
    throw std::invalid_argument(path + ": not a valid " + what + ": " + e.what());
  }
}

}  // namespace underwater_stereo
