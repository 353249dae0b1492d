// A hash of a place: per-node random numbers that depend on the node's reference position and
// a seed only, so every thread and rank count, and a node's daughters, draw the same values
// (Weibull strengths, docs/branching.md; nodal perturbation, docs/mesh.md).
#pragma once

#include <cstdint>
#include <cstring>

namespace brittle {

/// SplitMix64's finaliser: a well-mixed 64-bit hash step.
inline std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// The seed and the bits of the first n coordinates of x, mixed (-0.0 and 0.0 are one place).
inline std::uint64_t position_hash(std::uint64_t seed, const double* x, int n) {
  std::uint64_t h = mix64(seed + 0x9e3779b97f4a7c15ULL);
  for (int k = 0; k < n; ++k) {
    std::uint64_t bits;
    const double c = x[k] + 0.0;
    std::memcpy(&bits, &c, sizeof bits);
    h = mix64(h ^ (bits + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2)));
  }
  return h;
}

}  // namespace brittle
