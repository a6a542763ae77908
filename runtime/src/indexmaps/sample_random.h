#pragma once
// Counter-based random numbers for sample placement (docs/style.md §5): a value is
// a pure function of (seed, stream, index), so a sample's position does not
// depend on the order emitters are refreshed in.

#include <cstdint>

namespace svit::gl {

/// splitmix64 finaliser (Steele et al. 2014): a bijective 64-bit mix.
inline uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

/// Uniform in [0, 1) from (seed, stream, index): 24 random mantissa bits.
inline float uniform01(uint64_t seed, uint64_t stream, uint64_t index) {
  const uint64_t h = mix64(seed ^ mix64(stream ^ mix64(index)));
  return float(h >> 40) * (1.0f / 16777216.0f);
}

}  // namespace svit::gl
