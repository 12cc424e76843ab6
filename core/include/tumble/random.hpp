// SPDX-License-Identifier: MIT
/// @file random.hpp
/// A small deterministic random generator (SplitMix64). Unlike <random>'s distributions its
/// output is specified bit for bit, so scenes built from a seed are the same on every
/// platform and standard library.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "tumble/hd.hpp"
#include "tumble/math.hpp"

namespace tumble {

/// SplitMix64 (Steele, Lea, Flood 2014): 64-bit state, full period, passes BigCrush.
struct Rng {
  std::uint64_t state;
  explicit Rng(std::uint64_t seed = 0) : state(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1) with 24 random bits (exactly representable as float).
  float uniform() { return static_cast<float>(next() >> 40) * (1.0f / 16777216.0f); }
  /// Uniform in [lo, hi).
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  /// Uniform integer in [0, n) (n > 0); slight modulo bias is irrelevant here.
  std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>(next() % n); }
};

/// Mixes a seed and an index (a group's, a fill's, a body's) into an independent SplitMix64 seed.
inline std::uint64_t groupSeed(std::uint64_t seed, std::uint64_t index) {
  Rng mix(seed ^ (0xD1B54A32D192ED03ull * (index + 1)));
  return mix.next();
}

/// Shoemake's uniform random rotation from three uniforms in [0, 1) (Graphics Gems III,
/// "Uniform random rotations", 1992).
inline Quatf randomRotation(float u1, float u2, float u3) {
  constexpr float kTwoPi = 6.28318530717958647692f;
  const float a = std::sqrt(1.0f - u1);
  const float b = std::sqrt(u1);
  float s2 = 0.0f, c2 = 0.0f, s3 = 0.0f, c3 = 0.0f;
  sinCos(kTwoPi * u2, &s2, &c2);
  sinCos(kTwoPi * u3, &s3, &c3);
  return normalized(Quatf{b * c3, a * s2, a * c2, b * s3});
}

/// A vector of length `magnitude` in a uniformly random direction, from two uniforms.
inline Vec3f randomDirection(float u1, float u2, float magnitude) {
  constexpr float kTwoPi = 6.28318530717958647692f;
  const float z = 2.0f * u1 - 1.0f;
  const float rho = std::sqrt(std::max(0.0f, 1.0f - z * z));
  float s = 0.0f, c = 0.0f;
  sinCos(kTwoPi * u2, &s, &c);
  return {magnitude * rho * c, magnitude * rho * s, magnitude * z};
}

}  // namespace tumble
