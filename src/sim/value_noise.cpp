// SPDX-License-Identifier: BSD-3-Clause
#include "underwater_stereo/sim/value_noise.h"

#include <cmath>

namespace underwater_stereo {
namespace sim {
namespace {

inline float latticeValue(std::int32_t x, std::int32_t y, std::int32_t z, std::uint32_t seed) {
  std::uint32_t h = seed * 0x27d4eb2dU;
  h ^= static_cast<std::uint32_t>(x) * 0x9E3779B1U;
  h ^= static_cast<std::uint32_t>(y) * 0x85EBCA77U + (h << 6) + (h >> 2);
  h ^= static_cast<std::uint32_t>(z) * 0xC2B2AE3DU + (h << 6) + (h >> 2);
  h ^= h >> 15;
  h *= 0x2C1B3C6DU;
  h ^= h >> 12;
  h *= 0x297A2D39U;
  h ^= h >> 15;
  return static_cast<float>(h >> 8) * (1.0F / 16777216.0F);
}

inline float smooth(float t) { return t * t * (3.0F - 2.0F * t); }
inline float lerp(float a, float b, float t) { return a + (b - a) * t; }

}  // namespace

float valueNoise(float x, float y, float z, std::uint32_t seed) {
  const float fx = std::floor(x), fy = std::floor(y), fz = std::floor(z);
  const auto ix = static_cast<std::int32_t>(fx), iy = static_cast<std::int32_t>(fy), iz = static_cast<std::int32_t>(fz);
  const float tx = smooth(x - fx), ty = smooth(y - fy), tz = smooth(z - fz);
  const float c00 = lerp(latticeValue(ix, iy, iz, seed), latticeValue(ix + 1, iy, iz, seed), tx);
  const float c10 = lerp(latticeValue(ix, iy + 1, iz, seed), latticeValue(ix + 1, iy + 1, iz, seed), tx);
  const float c01 = lerp(latticeValue(ix, iy, iz + 1, seed), latticeValue(ix + 1, iy, iz + 1, seed), tx);
  const float c11 = lerp(latticeValue(ix, iy + 1, iz + 1, seed), latticeValue(ix + 1, iy + 1, iz + 1, seed), tx);
  return lerp(lerp(c00, c10, ty), lerp(c01, c11, ty), tz);
}

float textureNoise(float x, float y, float z, std::uint32_t seed) {
  return 0.6F * valueNoise(x, y, z, seed) + 0.4F * valueNoise(2.7F * x, 2.7F * y, 2.7F * z, seed + 17U);
}

}  // namespace sim
}  // namespace underwater_stereo
