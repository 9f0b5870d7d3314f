// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Reading /diagnostics in rostest nodes: a status by the end of its name, a value by its key.
#include <diagnostic_msgs/DiagnosticStatus.h>

#include <map>
#include <string>

namespace underwater_stereo {
namespace test {

/// The latest status whose name ends with `suffix` (a default status when none does).
inline diagnostic_msgs::DiagnosticStatus statusEndingWith(const std::map<std::string, diagnostic_msgs::DiagnosticStatus>& latest,
                                                          const std::string& suffix) {
  for (const auto& [name, status] : latest) {
    if (name.size() >= suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) return status;
  }
  return diagnostic_msgs::DiagnosticStatus();
}

/// The value of `key` in `s` ("" when absent).
inline std::string value(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key) {
  for (const auto& kv : s.values) {
    if (kv.key == key) return kv.value;
  }
  return "";
}

}  // namespace test
}  // namespace underwater_stereo
