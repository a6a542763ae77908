#pragma once
// The one random generator of the baker: a counter-based stream so every
// work item draws from its own sequence derived from stable ids, whatever
// thread runs it (docs/style.md §5). SplitMix64 (Steele, Lea & Flood 2014)
// mixes the key; PCG32's output permutation (O'Neill 2014) draws numbers.

#include <cstdint>

namespace svit::baker {

/// SplitMix64 finalizer: a bijective 64-bit mix.
constexpr uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

/// Hash of an ordered tuple of ids (seed, pass, batch, ray, ...).
constexpr uint64_t hashIds(uint64_t a, uint64_t b, uint64_t c = 0, uint64_t d = 0) {
  return mix64(mix64(mix64(mix64(a) ^ b) ^ c) ^ d);
}

/// PCG32 (XSH-RR) seeded from a 64-bit key; one per work item.
class Rng {
 public:
  explicit Rng(uint64_t key)
      : state_(mix64(key)), increment_((mix64(key ^ 0xda3e39cb94b95bdbull) << 1) | 1u) {
    next();
  }
  uint32_t next() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + increment_;
    const uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
  }
  /// Uniform in [0, 1): 24 random bits, so never rounds up to 1.
  float uniform() { return float(next() >> 8) * (1.0f / 16777216.0f); }
  /// Uniform in [0, 1) with 53 bits.
  double uniformDouble() {
    const uint64_t hi = next(), lo = next();
    return double(((hi << 32) | lo) >> 11) * (1.0 / 9007199254740992.0);
  }

 private:
  uint64_t state_;
  uint64_t increment_;
};

}  // namespace svit::baker
