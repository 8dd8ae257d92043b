// Deterministic, platform-independent random streams for phantoms: every consumer (a slice, a
// pattern, a tree) gets its own std::mt19937_64 seeded from (seed, stream, index) by a SplitMix64
// mix, and draws uniforms and normals by explicit formulas (the std:: distributions are
// implementation-defined, which would make outputs depend on the standard library).
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

#include "geometry/core/types.h"

namespace xsect {

inline std::uint64_t splitMix64(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

/// A generator for stream `stream` (a constant naming the purpose) and item `index`.
inline std::mt19937_64 makeStream(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  return std::mt19937_64(splitMix64(splitMix64(splitMix64(seed) ^ stream) ^ index));
}

/// Uniform in [0, 1) with 53 random bits.
inline double uniform01(std::mt19937_64& rng) {
  return double(rng() >> 11) * (1.0 / 9007199254740992.0);
}

inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return lo + (hi - lo) * uniform01(rng);
}

/// Standard normal by Box-Muller (one value per call, two uniforms).
inline double standardNormal(std::mt19937_64& rng) {
  const double u1 = 1.0 - uniform01(rng);  // (0, 1]
  const double u2 = uniform01(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
}

/// Uniformly distributed unit vector.
inline Vec3 randomUnitVector(std::mt19937_64& rng) {
  for (;;) {
    const Vec3 g(standardNormal(rng), standardNormal(rng), standardNormal(rng));
    const double n = g.norm();
    if (n > 1e-9) return g / n;
  }
}

}  // namespace xsect
