// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/common/whole_file.h"

#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>

namespace underwater_stereo {

namespace {

/// errno's text (std::strerror's, but safe from several threads at once), or `otherwise` when nothing set errno.
std::string systemReason(int error, const char* otherwise) {
  return error != 0 ? std::generic_category().message(error) : otherwise;
}

using File = std::unique_ptr<std::FILE, int (*)(std::FILE*)>;

File openForReading(const std::string& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);  // a missing file: fopen says so
  // fopen would open a folder and its first read fail with "Is a directory": said in our words, before reading.
  if (!error && std::filesystem::is_directory(status)) throw UnreadableFile(path, "a folder, not a file");
  // A device may never end (/dev/zero: memory grows until it runs out) and a pipe without a writer blocks fopen
  // for ever: only regular files are read.
  if (!error && !std::filesystem::is_regular_file(status)) {
    throw UnreadableFile(path, "not a regular file (a device, pipe or socket, which may never end or block)");
  }
  errno = 0;
  File file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) throw UnreadableFile(path, systemReason(errno, "cannot be opened"));
  return file;
}

}  // namespace

std::string readWholeFile(const std::string& path) {
  const File file = openForReading(path);
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    errno = 0;  // a successful fopen or fread may leave one behind
    const std::size_t got = std::fread(buffer, 1, sizeof buffer, file.get());
    const int error = errno;  // taken before append allocates
    if (got < sizeof buffer && std::ferror(file.get()) != 0) {
      throw UnreadableFile(path, systemReason(error, "an I/O error"));
    }
    bytes.append(buffer, got);
    if (got < sizeof buffer) return bytes;  // the end of the file
  }
}

void checkReadable(const std::string& path) { openForReading(path); }

}  // namespace underwater_stereo
