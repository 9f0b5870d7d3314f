// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/common/whole_file.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace underwater_stereo {

std::string readWholeFile(const std::string& path) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw std::invalid_argument(path + ": a folder, not a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot open the file");
  std::string bytes;
  try {
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  } catch (const std::exception& e) {  // libstdc++ throws on a read error (EIO; a folder is refused above)
    throw std::invalid_argument(path + ": cannot read the file (" + e.what() + ")");
  }
  if (in.bad()) throw std::invalid_argument(path + ": cannot read the file (an I/O error)");
  return bytes;
}

}  // namespace underwater_stereo
