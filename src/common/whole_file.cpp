// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/common/whole_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

namespace underwater_stereo {

namespace {

std::string systemReason(int error, const char* otherwise) { return error != 0 ? std::strerror(error) : otherwise; }

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

File openForReading(const std::string& path) {
  std::error_code ignored;
  // fopen would open a folder and its first read fail with "Is a directory": said in our words, before reading.
  if (std::filesystem::is_directory(path, ignored)) throw UnreadableFile(path, "a folder, not a file");
  errno = 0;
  File file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) throw UnreadableFile(path, systemReason(errno, "cannot be opened"));
  return file;
}

}  // namespace

std::string readWholeFile(const std::string& path) {
  const File file = openForReading(path);
  std::string bytes;
  errno = 0;  // a successful fopen may leave one behind
  char buffer[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, file.get())) > 0) bytes.append(buffer, got);
  if (std::ferror(file.get()) != 0) {
    throw UnreadableFile(path, "cannot be read (" + systemReason(errno, "an I/O error") + ")");
  }
  return bytes;
}

void checkReadable(const std::string& path) { openForReading(path); }

}  // namespace underwater_stereo
