// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A whole file read into memory, with the reason named when it cannot be (missing, not permitted, a folder,
/// a device or pipe, an I/O error): the one place every reader of files (images, VOC labels, YAML, records, lists,
/// models) learns why.

#include <stdexcept>
#include <string>

namespace underwater_stereo {

/// A file that cannot be read whole. what() is "PATH: REASON"; reason() alone lets a reader word its own message.
class UnreadableFile : public std::invalid_argument {
 public:
  UnreadableFile(const std::string& path, const std::string& reason)
      : std::invalid_argument(path + ": " + reason), reason_(reason) {}
  /// Why: the system's words where it gave some ("No such file or directory", "Permission denied", at a failed
  /// read "Input/output error"), "a folder, not a file", "not a regular file (...)", or, when the system named
  /// nothing, "cannot be opened" / "an I/O error".
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

/// Every byte of the file at `path`. @throw UnreadableFile when it cannot be opened, is a folder or no regular file,
/// or reading it fails.
std::string readWholeFile(const std::string& path);

/// For a file another library will read itself (OpenCV's FileStorage), which says only that it could not.
/// @throw UnreadableFile when it is a folder or no regular file, or cannot be opened for reading.
void checkReadable(const std::string& path);

}  // namespace underwater_stereo
