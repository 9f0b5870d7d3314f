// SPDX-License-Identifier: BSD-3-Clause
#pragma once
/// @file Cheap deterministic 3D value noise for surface texture (sand, dirt), so stereo has something to match.

#include <cstdint>

namespace underwater_stereo {
namespace sim {

/// Smooth noise in [0, 1] with features about 1 unit in size; deterministic in (x, y, z, seed).
float valueNoise(float x, float y, float z, std::uint32_t seed);

/// Two octaves of valueNoise (features of 1 and 1/2.7 units), in [0, 1].
float textureNoise(float x, float y, float z, std::uint32_t seed);

}  // namespace sim
}  // namespace underwater_stereo
