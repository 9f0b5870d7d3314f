// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Running a command-line tool from a test and reading what it wrote.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace underwater_stereo {

/// The exit status of `command` (a shell command line), its output and errors into `log`.
inline int runTool(const std::string& command, const std::filesystem::path& log = "/dev/null") {
  const int status = std::system((command + " >" + log.string() + " 2>&1").c_str());
  return WEXITSTATUS(status);
}

/// The whole of a text file ("" when it cannot be read).
inline std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace underwater_stereo
