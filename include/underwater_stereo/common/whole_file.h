// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file A whole file read into memory, with the reason named when it cannot be (a folder, an I/O error).

#include <string>

namespace underwater_stereo {

/// Every byte of the file at `path`.
/// @throw std::invalid_argument beginning with `path`: it cannot be opened, is a folder, or reading it failed.
std::string readWholeFile(const std::string& path);

}  // namespace underwater_stereo
