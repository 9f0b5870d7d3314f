// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/config/yaml_fields.h"

#include <algorithm>
#include <sstream>
#include <unordered_map>
#include <utility>

namespace underwater_stereo {

void YamlFields::optionalVector(const YAML::Node& map, const std::string& key, const std::string& path,
                                std::vector<double>& value, std::size_t expected_size) {
  if (!map.IsMap()) {
    notAMap(map, path);
    return;
  }
  const YAML::Node node = map[key];
  if (!node) return;
  std::vector<double> read;
  try {
    read = node.as<std::vector<double>>();
  } catch (const YAML::Exception&) {
    errors_.push_back(path + key + ": expected a list of " + std::to_string(expected_size) + " numbers, got '" +
                      YAML::Dump(node) + "'");
    return;
  }
  if (read.size() != expected_size) {
    errors_.push_back(path + key + ": expected " + std::to_string(expected_size) + " numbers, got " +
                      std::to_string(read.size()));
    return;
  }
  value = read;
}

void YamlFields::optionalVector3(const YAML::Node& map, const std::string& key, const std::string& path,
                                 Eigen::Vector3d& value) {
  std::vector<double> v{value.x(), value.y(), value.z()};
  optionalVector(map, key, path, v, 3);
  value = Eigen::Vector3d(v[0], v[1], v[2]);
}

void YamlFields::notAMap(const YAML::Node& node, const std::string& path) {
  const std::string problem = (path.empty() ? std::string("document") : path) + ": expected a map of key: value, got '" +
                              YAML::Dump(node) + "'";
  if (std::find(errors_.begin(), errors_.end(), problem) == errors_.end()) errors_.push_back(problem);
}

void YamlFields::onlyKeys(const YAML::Node& map, const std::string& path,
                          std::initializer_list<const char*> allowed) {
  onlyKeys(map, path, std::vector<std::string>(allowed.begin(), allowed.end()));
}

void YamlFields::onlyKeys(const YAML::Node& map, const std::string& path, const std::vector<std::string>& allowed) {
  if (!map.IsMap()) {
    notAMap(map, path);
    return;
  }
  for (const auto& entry : map) {
    const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : YAML::Dump(entry.first);
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string names;
      for (const std::string& name : allowed) names += (names.empty() ? "" : ", ") + name;
      errors_.push_back(path + key + ": unknown key (known: " + names + ")");
    }
  }
}

std::string joinProblems(const std::string& heading, const std::vector<std::string>& problems) {
  std::ostringstream out;
  out << heading << " (" << problems.size() << (problems.size() == 1 ? " problem" : " problems") << "):";
  for (const auto& p : problems) out << "\n  - " << p;
  return out.str();
}

namespace {

/// The maps and lists already walked, by where they begin in the text (a node's identity, but hashable): an alias makes
/// a node appear again, and an anchor on a map that holds its own alias (`a: &x {b: *x}`) a node that contains itself.
/// Nodes built in code, not parsed, have no position and share one bucket: walking many of them is quadratic (every
/// caller passes parsed files).
using Visited = std::unordered_multimap<std::size_t, YAML::Node>;

/// Whether `node` is in `visited`, adding it when not.
bool walkedBefore(const YAML::Node& node, Visited& visited) {
  const std::size_t at = static_cast<std::size_t>(node.Mark().pos);
  const auto [first, last] = visited.equal_range(at);
  if (std::any_of(first, last, [&](const auto& v) { return v.second.is(node); })) return true;
  visited.emplace(at, node);
  return false;
}

/// Each is walked once, each map's keys compared in one hash set: linear in the nodes of `node`.
void collectRepeatedKeys(const YAML::Node& node, const std::string& path, std::vector<std::string>& out,
                         Visited& visited) {
  if (!node.IsSequence() && !node.IsMap()) return;
  if (walkedBefore(node, visited)) return;
  if (node.IsSequence()) {
    std::size_t i = 0;
    for (const YAML::Node& item : node) collectRepeatedKeys(item, path + "[" + std::to_string(i++) + "]", out, visited);
    return;
  }
  std::unordered_map<std::string, int> seen;  // key, its first line
  for (const auto& entry : node) {
    const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : "(not a plain key)";
    const int line = entry.first.Mark().line + 1;
    const std::string name = path.empty() ? key : path + "." + key;
    if (const auto [first, added] = seen.emplace(key, line); !added) {
      out.push_back("key '" + name + "' twice (lines " + std::to_string(first->second) + " and " +
                    std::to_string(line) + ")");
    }
    collectRepeatedKeys(entry.second, name, out, visited);
  }
}

}  // namespace

std::vector<std::string> repeatedKeys(const YAML::Node& node) {
  std::vector<std::string> out;
  Visited visited;
  collectRepeatedKeys(node, "", out, visited);
  return out;
}

}  // namespace underwater_stereo
