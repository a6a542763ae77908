#pragma once
// Where the API abuse driver gets its choices from: a seeded generator for
// the CTest and the soak (the same seed replays the same calls), or the
// fuzzer's input bytes (tests/fuzz/fuzz_runtime_api.cpp). Every argument the
// driver passes is made from these draws, so a finding replays from its seed
// or its input alone.

#include <cstdint>

namespace svit::abuse {

class Draws {
 public:
  virtual ~Draws() = default;
  /// A choice in [0, n), n >= 1.
  virtual uint32_t below(uint32_t n) = 0;
  /// False once the source is spent (a fuzz input's last byte was used).
  virtual bool more() const = 0;
  /// A value in [0, 1] in 1/1024 steps.
  float unit() { return float(below(1025)) / 1024.0f; }
  /// A value in [lo, hi].
  float between(float lo, float hi) { return lo + (hi - lo) * unit(); }
  bool chance(uint32_t one_in) { return below(one_in) == 0; }
};

/// SplitMix64 (Steele, Lea and Flood 2014): small, seedable, and the same
/// sequence on every platform, which std:: distributions do not promise.
class SeededDraws final : public Draws {
 public:
  explicit SeededDraws(uint64_t seed) : state_(seed) {}
  uint32_t below(uint32_t n) override { return n <= 1 ? 0 : uint32_t(next() % n); }
  bool more() const override { return true; }

 private:
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  uint64_t state_;
};

}  // namespace svit::abuse
